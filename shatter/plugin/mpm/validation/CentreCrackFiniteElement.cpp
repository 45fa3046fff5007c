#include <shatter/plugin/mpm/validation/CentreCrackFiniteElement.h>

#include <Eigen/Dense>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

namespace shatter::mpm::validation {

namespace {

using Matrix3 = Eigen::Matrix3d;
using StrainMatrix = Eigen::Matrix<double, 3, 12>; // [ε_xx, ε_yy, γ_xy] from 6 nodes × (u_x, u_y)

// Node lines of one segment of length `length` with `n` elements, as distances from the tip
// (the segment's end at the tip first): corners at length·(i/n)², mid-sides halfway between
// corners (a 6-node triangle with straight sides needs its mid-side nodes at the midpoints).
std::vector<double> gradedFromTip(double length, int n) {
    std::vector<double> d(size_t(2 * n + 1));
    for (int i = 0; i <= n; ++i) d[size_t(2 * i)] = length * double(i) * i / (double(n) * n);
    for (int i = 0; i < n; ++i) d[size_t(2 * i + 1)] = 0.5 * (d[size_t(2 * i)] + d[size_t(2 * i + 2)]);
    return d;
}

Matrix3 elasticity(const CentreCrackFiniteElementCase& c) {
    Matrix3 D = Matrix3::Zero();
    if (c.analysis == Analysis::PlaneStress) {
        const double k = c.E / (1 - c.nu * c.nu);
        D << k, k * c.nu, 0, k * c.nu, k, 0, 0, 0, k * (1 - c.nu) / 2;
    } else {
        const double k = c.E / ((1 + c.nu) * (1 - 2 * c.nu));
        D << k * (1 - c.nu), k * c.nu, 0, k * c.nu, k * (1 - c.nu), 0, 0, 0, k * (1 - 2 * c.nu) / 2;
    }
    return D;
}

// A straight-sided 6-node triangle: corners 0, 1, 2 (counter-clockwise), mid-sides 3 (0-1),
// 4 (1-2), 5 (2-0).
struct Triangle6 {
    std::array<int, 6> node{};
    Eigen::Vector2d gradL[3];
    double area = 0;

    Triangle6(const std::array<int, 6>& n, const std::array<Eigen::Vector2d, 3>& p) : node(n) {
        const double twiceArea = (p[1] - p[0]).x() * (p[2] - p[0]).y() - (p[2] - p[0]).x() * (p[1] - p[0]).y();
        area = 0.5 * twiceArea;
        for (int i = 0; i < 3; ++i) {
            const Eigen::Vector2d& pj = p[size_t((i + 1) % 3)];
            const Eigen::Vector2d& pk = p[size_t((i + 2) % 3)];
            gradL[i] = Eigen::Vector2d(pj.y() - pk.y(), pk.x() - pj.x()) / twiceArea;
        }
    }
    // Gradients of the six shape functions at area coordinates L.
    std::array<Eigen::Vector2d, 6> shapeGradients(const Eigen::Vector3d& L) const {
        std::array<Eigen::Vector2d, 6> g;
        for (int i = 0; i < 3; ++i) g[size_t(i)] = (4 * L[i] - 1) * gradL[i];
        for (int i = 0; i < 3; ++i) {
            const int j = (i + 1) % 3;
            g[size_t(3 + i)] = 4 * (L[i] * gradL[j] + L[j] * gradL[i]);
        }
        return g;
    }
    StrainMatrix strainMatrix(const Eigen::Vector3d& L) const {
        const auto g = shapeGradients(L);
        StrainMatrix B = StrainMatrix::Zero();
        for (int k = 0; k < 6; ++k) {
            B(0, 2 * k) = g[size_t(k)].x();
            B(1, 2 * k + 1) = g[size_t(k)].y();
            B(2, 2 * k) = g[size_t(k)].y();
            B(2, 2 * k + 1) = g[size_t(k)].x();
        }
        return B;
    }
};

struct QuadraturePoint {
    Eigen::Vector3d L;
    double weight; // fraction of the area
};

// Degree 2 (the stiffness of a straight 6-node triangle, exactly).
const std::array<QuadraturePoint, 3> kDegree2{{{{2. / 3, 1. / 6, 1. / 6}, 1. / 3},
                                               {{1. / 6, 2. / 3, 1. / 6}, 1. / 3},
                                               {{1. / 6, 1. / 6, 2. / 3}, 1. / 3}}};
// Degree 4 (Dunavant): the J integrand (σ·∇u·∇q) is cubic.
constexpr double kA1 = 0.445948490915965, kB1 = 0.108103018168070, kW1 = 0.223381589678011;
constexpr double kA2 = 0.091576213509771, kB2 = 0.816847572980459, kW2 = 0.109951743655322;
const std::array<QuadraturePoint, 6> kDegree4{{{{kB1, kA1, kA1}, kW1},
                                               {{kA1, kB1, kA1}, kW1},
                                               {{kA1, kA1, kB1}, kW1},
                                               {{kB2, kA2, kA2}, kW2},
                                               {{kA2, kB2, kA2}, kW2},
                                               {{kA2, kA2, kB2}, kW2}}};

struct Mesh {
    std::vector<double> x, y; // node lines (corners and mid-sides), tip at (a, 0)
    std::vector<Triangle6> triangles;
    int columns() const { return int(x.size()); }
    int node(int i, int j) const { return j * columns() + i; }
    Eigen::Vector2d position(int n) const { return {x[size_t(n % columns())], y[size_t(n / columns())]}; }
    int nodes() const { return int(x.size() * y.size()); }
};

Mesh buildMesh(const CentreCrackFiniteElementCase& c, int refinement) {
    const double halfWidth = 0.5 * c.width, halfHeight = 0.5 * c.height, ligament = halfWidth - c.a;
    // Division counts ∝ √length: the first element from the tip is then the same size in
    // each segment (length/n²).
    const auto count = [&](double length) {
        return refinement * std::max(1, int(std::lround(c.divisions * std::sqrt(length / c.a))));
    };
    Mesh m;
    const std::vector<double> crack = gradedFromTip(c.a, refinement * c.divisions);
    const std::vector<double> beyond = gradedFromTip(ligament, count(ligament));
    for (size_t i = crack.size(); i-- > 0;) m.x.push_back(c.a - crack[i]);
    for (size_t i = 1; i < beyond.size(); ++i) m.x.push_back(c.a + beyond[i]);
    m.y = gradedFromTip(halfHeight, count(halfHeight));
    const int cellsX = (m.columns() - 1) / 2, cellsY = (int(m.y.size()) - 1) / 2;
    for (int cj = 0; cj < cellsY; ++cj)
        for (int ci = 0; ci < cellsX; ++ci) {
            const int I = 2 * ci, J = 2 * cj;
            const auto p = [&](int i, int j) { return m.position(m.node(i, j)); };
            m.triangles.emplace_back(std::array<int, 6>{m.node(I, J), m.node(I + 2, J), m.node(I + 2, J + 2),
                                                        m.node(I + 1, J), m.node(I + 2, J + 1), m.node(I + 1, J + 1)},
                                     std::array<Eigen::Vector2d, 3>{p(I, J), p(I + 2, J), p(I + 2, J + 2)});
            m.triangles.emplace_back(std::array<int, 6>{m.node(I, J), m.node(I + 2, J + 2), m.node(I, J + 2),
                                                        m.node(I + 1, J + 1), m.node(I + 1, J + 2), m.node(I, J + 1)},
                                     std::array<Eigen::Vector2d, 3>{p(I, J), p(I + 2, J + 2), p(I, J + 2)});
        }
    return m;
}

// Displacements (u_x, u_y per node) of the quarter plate.
Eigen::VectorXd solveDisplacements(const CentreCrackFiniteElementCase& c, const Mesh& m) {
    const int dofs = 2 * m.nodes();
    // Symmetry: u_x = 0 on x = 0, u_y = 0 on the ligament (y = 0, x ≥ a, the tip included).
    std::vector<int> freeIndex(size_t(dofs), 0);
    for (int j = 0; j < int(m.y.size()); ++j) freeIndex[size_t(2 * m.node(0, j))] = -1;
    for (int i = 0; i < m.columns(); ++i)
        if (m.x[size_t(i)] >= c.a) freeIndex[size_t(2 * m.node(i, 0) + 1)] = -1;
    int free = 0;
    for (int& f : freeIndex)
        if (f == 0) f = free++;

    const Matrix3 D = elasticity(c);
    std::vector<Eigen::Triplet<double>> entries;
    entries.reserve(m.triangles.size() * 144 / 2);
    for (const Triangle6& t : m.triangles) {
        Eigen::Matrix<double, 12, 12> Ke = Eigen::Matrix<double, 12, 12>::Zero();
        for (const QuadraturePoint& q : kDegree2) {
            const StrainMatrix B = t.strainMatrix(q.L);
            Ke += (q.weight * t.area) * B.transpose() * D * B;
        }
        for (int r = 0; r < 12; ++r) {
            const int fr = freeIndex[size_t(2 * t.node[size_t(r / 2)] + r % 2)];
            if (fr < 0) continue;
            for (int s = 0; s < 12; ++s) {
                const int fs = freeIndex[size_t(2 * t.node[size_t(s / 2)] + s % 2)];
                if (fs >= 0 && fs <= fr) entries.emplace_back(fr, fs, Ke(r, s)); // lower triangle
            }
        }
    }
    Eigen::SparseMatrix<double> K(free, free);
    K.setFromTriplets(entries.begin(), entries.end());

    // Uniform traction σ on the top edge: a quadratic edge takes 1/6, 2/3, 1/6 of σ·length.
    Eigen::VectorXd f = Eigen::VectorXd::Zero(free);
    const int top = int(m.y.size()) - 1;
    for (int I = 0; I + 2 < m.columns(); I += 2) {
        const double length = m.x[size_t(I + 2)] - m.x[size_t(I)];
        const double share[3] = {1. / 6, 2. / 3, 1. / 6};
        for (int k = 0; k < 3; ++k) f[freeIndex[size_t(2 * m.node(I + k, top) + 1)]] += share[k] * c.sigma * length;
    }
    Eigen::SimplicialLLT<Eigen::SparseMatrix<double>, Eigen::Lower> solver(K);
    if (solver.info() != Eigen::Success)
        throw std::runtime_error("centre-crack FE: stiffness matrix not positive definite");
    const Eigen::VectorXd uFree = solver.solve(f);
    Eigen::VectorXd u = Eigen::VectorXd::Zero(dofs);
    for (int d = 0; d < dofs; ++d)
        if (freeIndex[size_t(d)] >= 0) u[d] = uFree[freeIndex[size_t(d)]];
    return u;
}

// The domain J-integral over the upper half with q falling from 1 at r1 to 0 at r2, doubled.
double domainJ(const CentreCrackFiniteElementCase& c, const Mesh& m, const Eigen::VectorXd& u, double r1, double r2) {
    const Eigen::Vector2d tip(c.a, 0);
    const Matrix3 D = elasticity(c);
    std::vector<double> q(size_t(m.nodes()));
    for (int n = 0; n < m.nodes(); ++n)
        q[size_t(n)] = std::clamp((r2 - (m.position(n) - tip).norm()) / (r2 - r1), 0.0, 1.0);
    double J = 0;
    for (const Triangle6& t : m.triangles) {
        bool flat = true; // ∇q = 0 over the element: no contribution
        for (int k = 1; k < 6; ++k) flat = flat && q[size_t(t.node[size_t(k)])] == q[size_t(t.node[0])];
        if (flat) continue;
        Eigen::Matrix<double, 12, 1> ue;
        for (int k = 0; k < 6; ++k) ue.segment<2>(2 * k) = u.segment<2>(2 * t.node[size_t(k)]);
        for (const QuadraturePoint& p : kDegree4) {
            const auto g = t.shapeGradients(p.L);
            Eigen::Matrix2d gradU = Eigen::Matrix2d::Zero(); // gradU(i, j) = ∂u_i/∂x_j
            Eigen::Vector2d gradQ = Eigen::Vector2d::Zero();
            for (int k = 0; k < 6; ++k) {
                gradU.row(0) += ue[2 * k] * g[size_t(k)].transpose();
                gradU.row(1) += ue[2 * k + 1] * g[size_t(k)].transpose();
                gradQ += q[size_t(t.node[size_t(k)])] * g[size_t(k)];
            }
            const Eigen::Vector3d strain(gradU(0, 0), gradU(1, 1), gradU(0, 1) + gradU(1, 0));
            const Eigen::Vector3d s = D * strain; // σ_xx, σ_yy, σ_xy
            const double w = 0.5 * s.dot(strain);
            const double ix = s[0] * gradU(0, 0) + s[2] * gradU(1, 0) - w; // (σ_1j u_j,1 ... ) j = x
            const double iy = s[2] * gradU(0, 0) + s[1] * gradU(1, 0);     // j = y
            J += p.weight * t.area * (ix * gradQ.x() + iy * gradQ.y());
        }
    }
    return 2 * J;
}

double effectiveModulus(const CentreCrackFiniteElementCase& c) {
    return c.analysis == Analysis::PlaneStress ? c.E : c.E / (1 - c.nu * c.nu);
}

} // namespace

double CentreCrackFiniteElementResult::F(const CentreCrackFiniteElementCase& c) const {
    return KI / (c.sigma * std::sqrt(std::numbers::pi * c.a));
}

CentreCrackFiniteElementMesh solveCentreCrackFiniteElement(const CentreCrackFiniteElementCase& c, int refinement) {
    if (!(c.a > 0 && c.a < 0.5 * c.width && c.height > 0 && c.divisions > 0 && refinement > 0))
        throw std::invalid_argument("centre-crack FE: needs 0 < a < W/2, H > 0 and divisions > 0 (a " +
                                    std::to_string(c.a) + ", W " + std::to_string(c.width) + ")");
    const Mesh m = buildMesh(c, refinement);
    const Eigen::VectorXd u = solveDisplacements(c, m);
    const double scale = std::min({c.a, 0.5 * c.width - c.a, 0.5 * c.height});
    const double E = effectiveModulus(c);
    CentreCrackFiniteElementMesh r;
    r.elements = int(m.triangles.size());
    r.nodes = m.nodes();
    r.KI = std::sqrt(std::max(0.0, domainJ(c, m, u, 0.25 * scale, 0.5 * scale)) * E);
    r.KIinnerDomain = std::sqrt(std::max(0.0, domainJ(c, m, u, 0.125 * scale, 0.25 * scale)) * E);
    return r;
}

CentreCrackFiniteElementResult centreCrackFiniteElement(const CentreCrackFiniteElementCase& c) {
    CentreCrackFiniteElementResult r;
    for (int k = 0; k < 3; ++k) r.meshes[size_t(k)] = solveCentreCrackFiniteElement(c, 1 << k);
    const double k1 = r.meshes[0].KI, k2 = r.meshes[1].KI, k3 = r.meshes[2].KI;
    const double d12 = k1 - k2, d23 = k2 - k3;
    r.KI = k3;
    if (d12 * d23 > 0 && std::abs(d23) < std::abs(d12)) {
        // K(n) ≈ K + C n^−p with n doubling: the differences shrink by 2^p.
        r.order = std::log2(d12 / d23);
        r.KI = k3 - d23 / (std::exp2(r.order) - 1);
    }
    r.errorEstimate = std::abs(r.KI - k3) / r.KI;
    r.converged = std::abs(d23) < c.tolerance * std::abs(k3) && std::isfinite(r.KI);
    return r;
}

} // namespace shatter::mpm::validation
