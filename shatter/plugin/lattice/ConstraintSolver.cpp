#include <shatter/plugin/lattice/ConstraintSolver.h>

#include <shatter/plugin/common/SettingCheck.h>

#include <cmath>
#include <unordered_map>

namespace shatter::lattice {

ConstraintSystem::ConstraintSystem(const Lattice& lattice, std::vector<int> particles, std::vector<int> links)
    : particles_(std::move(particles)) {
    std::unordered_map<int, int> local;
    local.reserve(particles_.size() * 2);
    for (int i = 0; i < int(particles_.size()); ++i) {
        local.emplace(particles_[i], i);
        inverseMass_.push_back(lattice.inverseMass(particles_[i]));
    }
    for (int k : links) {
        const Link& l = lattice.links()[k];
        if (l.broken) continue;
        const auto a = local.find(l.a), b = local.find(l.b);
        if (a == local.end() || b == local.end()) continue;
        if (inverseMass_[a->second] == 0.0 && inverseMass_[b->second] == 0.0) continue;
        links_.push_back(k);
        rowA_.push_back(a->second);
        rowB_.push_back(b->second);
        normal_.push_back(l.normal);
        length_.push_back(l.length);
    }
    scratch_.resize(particles_.size());
}

void ConstraintSystem::multiply(const Eigen::VectorXd& x, Eigen::VectorXd& y) const {
    // Jᵀ x gives the force on each particle; M⁻¹ turns it into an acceleration; J reads
    // back each link's relative acceleration along its normal.
    for (auto& f : scratch_) f.setZero();
    for (int k = 0; k < rowCount(); ++k) {
        const Eigen::Vector3d f = normal_[k] * x[k];
        scratch_[rowA_[k]] += f;
        scratch_[rowB_[k]] -= f;
    }
    for (int i = 0; i < particleCount(); ++i) scratch_[i] *= inverseMass_[i];
    y.resize(rowCount());
    for (int k = 0; k < rowCount(); ++k) y[k] = normal_[k].dot(scratch_[rowA_[k]] - scratch_[rowB_[k]]);
}

Eigen::VectorXd ConstraintSystem::jacobianTimes(const Eigen::VectorXd& v) const {
    Eigen::VectorXd out(rowCount());
    for (int k = 0; k < rowCount(); ++k)
        out[k] = normal_[k].dot(v.segment<3>(3 * rowA_[k]) - v.segment<3>(3 * rowB_[k]));
    return out;
}

Eigen::VectorXd ConstraintSystem::constraintForces(const Eigen::VectorXd& lambda) const {
    Eigen::VectorXd f = Eigen::VectorXd::Zero(3 * particleCount());
    for (int k = 0; k < rowCount(); ++k) {
        f.segment<3>(3 * rowA_[k]) += normal_[k] * lambda[k];
        f.segment<3>(3 * rowB_[k]) -= normal_[k] * lambda[k];
    }
    return f;
}

Eigen::VectorXd ConstraintSystem::rightHandSide(const Eigen::VectorXd& forces, const Eigen::Vector3d& omega) const {
    Eigen::VectorXd b(rowCount());
    for (int k = 0; k < rowCount(); ++k) {
        const Eigen::Vector3d accA = inverseMass_[rowA_[k]] * forces.segment<3>(3 * rowA_[k]);
        const Eigen::Vector3d accB = inverseMass_[rowB_[k]] * forces.segment<3>(3 * rowB_[k]);
        // J̇q̇ for a distance constraint is |v_rel|²/d - (n·v_rel)²/d; in a rigid rotation
        // v_rel = ω × d is normal to d, so only |ω × d|²/d is left.
        const double centripetal = omega.cross(normal_[k]).squaredNorm() * length_[k];
        b[k] = -centripetal - normal_[k].dot(accA - accB);
    }
    return b;
}

void ConstraintSolverSettings::check(const std::string& body) const {
    requireSetting(tolerance > 0.0 && tolerance < 1.0, body, "solver tolerance", "in (0, 1)", tolerance);
    requireAtLeast(body, "solver max iterations", maxIterations, 1);
}

SolveResult ConstraintSystem::solve(const Eigen::VectorXd& b, Eigen::VectorXd& x, const ConstraintSolverSettings& s) const {
    SolveResult result;
    const int n = rowCount();
    if (x.size() != n) x = Eigen::VectorXd::Zero(n);
    const double bNorm = b.norm();
    if (n == 0 || bNorm == 0.0) {
        x.setZero();
        result.converged = true;
        return result;
    }
    // Jacobi preconditioning: A_kk = |n_k|² (1/m_a + 1/m_b) = 1/m_a + 1/m_b, which varies with
    // the masses of a link's two tets (and halves next to a fixed one).
    Eigen::VectorXd inverseDiagonal(n);
    for (int k = 0; k < n; ++k) inverseDiagonal[k] = 1.0 / (inverseMass_[rowA_[k]] + inverseMass_[rowB_[k]]);
    Eigen::VectorXd r(n), z(n), p(n), ap(n);
    multiply(x, ap);
    r = b - ap;
    z = inverseDiagonal.cwiseProduct(r);
    double rz = r.dot(z), rr = r.squaredNorm();
    const double goal = s.tolerance * bNorm;
    p = z;
    while (std::sqrt(rr) > goal && result.iterations < s.maxIterations) {
        multiply(p, ap);
        const double pap = p.dot(ap);
        if (!(pap > 0.0)) break; // p in the null space: nothing left that the matrix can reach
        const double alpha = rz / pap;
        x += alpha * p;
        r -= alpha * ap;
        rr = r.squaredNorm();
        ++result.iterations;
        if (s.onIteration) s.onIteration(result.iterations, x, std::sqrt(rr) / bNorm);
        z = inverseDiagonal.cwiseProduct(r);
        const double rzNew = r.dot(z);
        p = z + (rzNew / rz) * p;
        rz = rzNew;
    }
    result.residual = std::sqrt(rr) / bNorm;
    result.converged = std::sqrt(rr) <= goal;
    return result;
}

Eigen::SparseMatrix<double> ConstraintSystem::assemble() const {
    // A_kl = n_k·n_l (±1/m of each shared particle): links meet only at their end particles.
    std::vector<std::vector<int>> rowsOf(particleCount());
    for (int k = 0; k < rowCount(); ++k) {
        rowsOf[rowA_[k]].push_back(k);
        rowsOf[rowB_[k]].push_back(k);
    }
    std::vector<Eigen::Triplet<double>> entries;
    for (int i = 0; i < particleCount(); ++i) {
        if (inverseMass_[i] == 0.0) continue;
        for (int k : rowsOf[i])
            for (int l : rowsOf[i]) {
                const double sk = rowA_[k] == i ? 1.0 : -1.0, sl = rowA_[l] == i ? 1.0 : -1.0;
                entries.emplace_back(k, l, sk * sl * inverseMass_[i] * normal_[k].dot(normal_[l]));
            }
    }
    Eigen::SparseMatrix<double> a(rowCount(), rowCount());
    a.setFromTriplets(entries.begin(), entries.end());
    return a;
}

} // namespace shatter::lattice
