#include <shatter/plugin/mpm/JIntegral.h>

#include <shatter/plugin/mpm/BSpline.h>

#include <Eigen/Cholesky>

#include <array>
#include <cmath>
#include <numbers>

namespace shatter::mpm {

namespace {

constexpr int kQuantities = 9; // σxx σxy σyy, ∂u (4), W, kinetic
using Row = Eigen::Matrix<double, 1, kQuantities>;

Row quantities(const NearTipSample& p) {
    Row q;
    q << p.sigma(0, 0), 0.5 * (p.sigma(0, 1) + p.sigma(1, 0)), p.sigma(1, 1), p.gradU(0, 0), p.gradU(0, 1),
        p.gradU(1, 0), p.gradU(1, 1), p.W, p.kinetic;
    return q;
}

struct PointValues {
    Mat2 sigma, gradU;
    double W = 0, kinetic = 0;
    double density = 0; // Σ N V / dx²: ≈ 1 inside a body, ½ on a straight face, 0 outside
};

// Weighted least squares of the quantities on the basis {1, x, y, x², xy, y²} (or its first
// `terms` members) in cell units around the point; the value at the point is the constant.
template <int Terms>
bool fit(const std::vector<Vec2>& d, const std::vector<double>& w, const std::vector<Row>& q, Row& value) {
    using Basis = Eigen::Matrix<double, Terms, 1>;
    Eigen::Matrix<double, Terms, Terms> M = Eigen::Matrix<double, Terms, Terms>::Zero();
    Eigen::Matrix<double, Terms, kQuantities> rhs = Eigen::Matrix<double, Terms, kQuantities>::Zero();
    for (size_t i = 0; i < d.size(); ++i) {
        const double full[6] = {1, d[i].x(), d[i].y(), d[i].x() * d[i].x(), d[i].x() * d[i].y(), d[i].y() * d[i].y()};
        const Basis b = Eigen::Map<const Basis>(full);
        M += w[i] * b * b.transpose();
        rhs += w[i] * b * q[i];
    }
    const Eigen::LDLT<Eigen::Matrix<double, Terms, Terms>> ldlt(M);
    // rcond guards against too few, or collinear, particles: 1e-7 keeps the fit's noise
    // amplification below ~1e3 (its square root), far from round-off trouble.
    if (ldlt.info() != Eigen::Success || ldlt.rcond() < 1e-7) return false;
    value = ldlt.solve(rhs).row(0);
    return true;
}

bool transfer(const std::vector<NearTipSample>& particles, const Vec2& point, const Vec2& sidePoint,
              const CrackSegments& segments, double dx, PointValues& out) {
    const double reach = kernelRadius(KernelType::Cubic) * dx;
    std::vector<int> candidates;
    segments.candidates(Box{sidePoint - Vec2::Constant(reach + dx), sidePoint + Vec2::Constant(reach + dx)}, candidates);
    std::vector<Vec2> d;
    std::vector<double> w;
    std::vector<Row> q;
    double density = 0;
    for (const NearTipSample& p : particles) {
        const double N = pointWeight<CubicSpline>(p.x - point, 1 / dx);
        if (N <= 0) continue;
        int crossed = -1;
        if (segments.field(p.x, sidePoint, candidates, crossed, true) != 0) continue; // other side
        d.push_back((p.x - point) / dx);
        w.push_back(p.mass * N); // eq. 25's mass weighting
        q.push_back(quantities(p));
        density += N * p.volume / (dx * dx);
    }
    out.density = density;
    Row value;
    bool ok = d.size() >= 6 && fit<6>(d, w, q, value);
    if (!ok) ok = d.size() >= 3 && fit<3>(d, w, q, value);
    if (!ok) ok = !d.empty() && fit<1>(d, w, q, value);
    if (!ok) return false;
    out.sigma << value(0), value(1), value(1), value(2);
    out.gradU << value(3), value(4), value(5), value(6);
    out.W = value(7);
    out.kinetic = value(8);
    return true;
}

// Eq. 28: F_m = (W + K) n_m − (σ n)·∂u/∂x_m.
Vec2 integrand(const PointValues& v, const Vec2& n) {
    const Vec2 traction = v.sigma * n;
    return (v.W + v.kinetic) * n - v.gradU.transpose() * traction;
}

// Williams' near-tip field of unit K (mode 0: I, 1: II) at polar (r, θ) in the tip's frame:
// the stress and ∂u/∂x (along the crack). ∂u/∂x = cosθ ∂u/∂r − sinθ/r ∂u/∂θ with u ∝ √r; the
// angular derivative by central differences of the closed form (smooth through θ = ±π).
struct AuxiliaryField {
    Mat2 sigma;
    Vec2 dUdx;
};

AuxiliaryField williamsField(int mode, double r, double theta, double mu, double kappa) {
    const auto displacement = [&](double t) {
        const double c = std::cos(t / 2), s = std::sin(t / 2);
        const double scale = std::sqrt(r / (2 * std::numbers::pi)) / (2 * mu);
        return mode == 0 ? Vec2(scale * c * (kappa - 1 + 2 * s * s), scale * s * (kappa + 1 - 2 * c * c))
                         : Vec2(scale * s * (kappa + 1 + 2 * c * c), -scale * c * (kappa - 1 - 2 * s * s));
    };
    const double h = 1e-5;
    const Vec2 u = displacement(theta), dUdTheta = (displacement(theta + h) - displacement(theta - h)) / (2 * h);
    AuxiliaryField f;
    f.dUdx = std::cos(theta) * u / (2 * r) - std::sin(theta) / r * dUdTheta;
    const double k = 1 / std::sqrt(2 * std::numbers::pi * r);
    const double c = std::cos(theta / 2), s = std::sin(theta / 2);
    const double c3 = std::cos(1.5 * theta), s3 = std::sin(1.5 * theta);
    double xx, yy, xy;
    if (mode == 0) {
        xx = k * c * (1 - s * s3);
        yy = k * c * (1 + s * s3);
        xy = k * c * s * c3;
    } else {
        xx = -k * s * (2 + c * c3);
        yy = k * s * c * c3;
        xy = k * c * (1 - s * s3);
    }
    f.sigma << xx, xy, xy, yy;
    return f;
}

// The interaction integrals with the unit mode I and mode II fields (see JIntegral.h).
void interactionIntegrals(const std::vector<PointValues>& values, const std::vector<double>& angles,
                          const Vec2& direction, double radius, double simpsonStep, const ContourSettings& settings,
                          JIntegralResult& result) {
    Mat2 R;
    R.col(0) = direction;
    R.col(1) = leftNormal(direction);
    const int n = int(values.size()) - 1;
    double M[2] = {0, 0};
    for (int k = 0; k <= n; ++k) {
        const Mat2 sigma = R.transpose() * values[size_t(k)].sigma * R;
        const Mat2 grad = R.transpose() * values[size_t(k)].gradU * R;
        const Mat2 strain = 0.5 * (grad + grad.transpose());
        const Vec2 normal(std::cos(angles[size_t(k)]), std::sin(angles[size_t(k)]));
        const double weight = (k == 0 || k == n ? 1.0 : k % 2 ? 4.0 : 2.0) * simpsonStep;
        for (int mode = 0; mode < 2; ++mode) {
            const AuxiliaryField a =
                williamsField(mode, radius, angles[size_t(k)], settings.shearModulus, settings.kappa);
            // σ:ε_aux = σ_aux:ε (one elastic material), which needs no auxiliary strain.
            const double mutualW = (a.sigma.array() * strain.array()).sum();
            M[mode] += weight * (mutualW * normal.x() - (sigma * normal).dot(a.dUdx) -
                                 (a.sigma * normal).dot(grad.col(0)));
        }
    }
    // K = M E'/2, E' = 8μ/(κ + 1).
    const double modulus = 8 * settings.shearModulus / (settings.kappa + 1);
    result.KIinteraction = 0.5 * modulus * M[0];
    result.KIIinteraction = 0.5 * modulus * M[1];
}

} // namespace

bool contourCrackCrossing(const std::vector<Vec2>& points, int tip, double radius, Vec2& crossing) {
    const size_t n = points.size();
    const Vec2 centre = tip == 0 ? points[0] : points[n - 1];
    for (size_t k = 1; k < n; ++k) {
        const Vec2 a = tip == 0 ? points[k - 1] : points[n - k];
        const Vec2 b = tip == 0 ? points[k] : points[n - 1 - k];
        if ((b - centre).norm() < radius) continue;
        // |a + t(b − a) − centre| = radius for t in [0, 1], a inside.
        const Vec2 d = b - a, f = a - centre;
        const double A = d.squaredNorm(), B = 2 * f.dot(d), C = f.squaredNorm() - radius * radius;
        const double t = (-B + std::sqrt(std::max(0.0, B * B - 4 * A * C))) / (2 * A);
        crossing = a + t * d;
        return true;
    }
    return false;
}

JIntegralResult jIntegral(const std::vector<NearTipSample>& particles, const Vec2& tipPosition,
                          const Vec2& direction, const Vec2& crossing, const CrackSegments& segments,
                          const ContourSettings& settings) {
    JIntegralResult result;
    const double r = settings.radius;
    const Vec2 c = crossing - tipPosition;
    // The crack's angle on the circle, measured from the growth direction, in (−π, π];
    // the contour runs from it (lower face) to it + 2π (upper face).
    const double crackAngle = std::atan2(direction.x() * c.y() - direction.y() * c.x(), direction.dot(c));
    const double start = crackAngle > 0 ? crackAngle - 2 * std::numbers::pi : crackAngle;
    const double base = std::atan2(direction.y(), direction.x());
    const int n = settings.segments;
    const double step = 2 * std::numbers::pi / n;
    // The side test needs a point strictly on one side; 1e-3 of a segment is enough and
    // does not move the fit (which is centred on the true contour point).
    const double nudge = 1e-3 * step;
    std::vector<Vec2> integrands;
    std::vector<PointValues> values;
    std::vector<double> angles; // from the tip direction
    for (int k = 0; k <= n; ++k) {
        const double phi = base + start + k * step;
        const double sidePhi = phi + (k == 0 ? nudge : k == n ? -nudge : 0);
        const Vec2 normal(std::cos(phi), std::sin(phi));
        const Vec2 point = tipPosition + r * normal;
        const Vec2 sidePoint = tipPosition + r * Vec2(std::cos(sidePhi), std::sin(sidePhi));
        result.contour.push_back(point);
        PointValues v;
        // Below 0.3 the point is outside the body (a face is 0.5): the contour is not closed
        // in material and J would be meaningless.
        if (!transfer(particles, point, sidePoint, segments, settings.dx, v) || v.density < 0.3) return result;
        integrands.push_back(integrand(v, normal));
        values.push_back(v);
        angles.push_back(start + k * step);
    }
    // Simpson's rule in the angle, ds = r dφ.
    Vec2 sum = Vec2::Zero();
    for (int k = 0; k <= n; ++k) sum += (k == 0 || k == n ? 1.0 : k % 2 ? 4.0 : 2.0) * integrands[size_t(k)];
    result.Jvector = sum * (r * step / 3);
    result.J = result.Jvector.dot(direction);
    result.valid = true;
    interactionIntegrals(values, angles, direction, r, r * step / 3, settings, result);
    return result;
}

} // namespace shatter::mpm
