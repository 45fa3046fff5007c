#include <shatter/plugin/oriented/RotationExtraction.h>

#include <Eigen/Cholesky>
#include <cmath>

namespace shatter::oriented {

namespace {

// Step (rotation vector, in the frame of R) that increases trace(RᵀA). With M = RᵀA,
// trace((R exp[θ])ᵀ A) ≈ trace M + θ·τ − ½ θᵀ H θ, τ = (M₂₁−M₁₂, M₀₂−M₂₀, M₁₀−M₀₁),
// H = trace(M) 𝟙 − sym(M). Near the answer H is positive definite and the Newton step
// H⁻¹τ converges quadratically. Elsewhere (far away, or a rank-deficient A) Müller's step
// τ / |trace M| is used: it always increases the fit and is finite for any A.
Eigen::Vector3d fitStep(const Eigen::Matrix3d& M) {
    const Eigen::Vector3d torque(M(2, 1) - M(1, 2), M(0, 2) - M(2, 0), M(1, 0) - M(0, 1));
    const Eigen::Matrix3d H = M.trace() * Eigen::Matrix3d::Identity() - 0.5 * (M + M.transpose());
    const Eigen::LLT<Eigen::Matrix3d> llt(H);
    const double scale = M.norm();
    if (llt.info() == Eigen::Success && llt.matrixL().toDenseMatrix().diagonal().minCoeff() > 1e-6 * std::sqrt(scale)) {
        const Eigen::Vector3d newton = llt.solve(torque);
        if (newton.allFinite() && newton.norm() < 0.5) return newton;
    }
    return torque / (std::abs(M.trace()) + 1e-9 * scale + 1e-300);
}

} // namespace

Eigen::Quaterniond extractRotation(const Eigen::Matrix3d& A, Eigen::Quaterniond q, int maxIterations,
                                   double tolerance) {
    for (int iteration = 0; iteration < maxIterations; ++iteration) {
        const Eigen::Vector3d step = fitStep(q.toRotationMatrix().transpose() * A);
        const double angle = step.norm();
        if (!(angle > tolerance)) break; // also stops on NaN
        q = q * Eigen::Quaterniond(Eigen::AngleAxisd(angle, step / angle));
        q.normalize();
    }
    return q;
}

} // namespace shatter::oriented
