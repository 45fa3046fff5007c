#include <shatter/plugin/oriented/RotationExtraction.h>

#include <cmath>

namespace shatter::oriented {

namespace {

// Step (rotation vector, in the frame of R) that increases trace(RᵀA). With M = RᵀA,
// trace((R exp[θ])ᵀ A) ≈ trace M + θ·τ − ½ θᵀ H θ, τ = (M₂₁−M₁₂, M₀₂−M₂₀, M₁₀−M₀₁),
// H = trace(M) 𝟙 − sym(M). Near the answer H is positive definite and the Newton step
// H⁻¹τ converges quadratically. Elsewhere (far away, or a rank-deficient A) Müller's step
// τ / |trace M| is used: it always increases the fit and is finite for any A.
Eigen::Vector3d fitStep(const Eigen::Matrix3d& M, bool& newton) {
    newton = false;
    const Eigen::Vector3d torque(M(2, 1) - M(1, 2), M(0, 2) - M(2, 0), M(1, 0) - M(0, 1));
    const double trace = M.trace();
    // The size of M for the degeneracy floors: its entry-wise 1-norm, within a factor 3 of the
    // Frobenius norm and without its square root (this runs once per group and sweep).
    const double scale = M.cwiseAbs().sum();
    // H = trace(M) 𝟙 − sym(M), positive definite when its three pivots are (the LLT's
    // squared diagonal); solved by its adjugate, a fraction of a factorisation's cost.
    const double h00 = trace - M(0, 0), h11 = trace - M(1, 1), h22 = trace - M(2, 2);
    const double h01 = -0.5 * (M(0, 1) + M(1, 0)), h02 = -0.5 * (M(0, 2) + M(2, 0)), h12 = -0.5 * (M(1, 2) + M(2, 1));
    const double c00 = h11 * h22 - h12 * h12, c01 = h02 * h12 - h01 * h22, c02 = h01 * h12 - h02 * h11;
    const double minor2 = h00 * h11 - h01 * h01;
    const double det = h00 * c00 + h01 * c01 + h02 * c02;
    const double floor = 1e-12 * scale;
    if (h00 > floor && minor2 > floor * h00 && det > floor * minor2) {
        const double c11 = h00 * h22 - h02 * h02, c12 = h01 * h02 - h00 * h12;
        const double inverse = 1.0 / det;
        const Eigen::Vector3d step = inverse * Eigen::Vector3d(c00 * torque.x() + c01 * torque.y() + c02 * torque.z(),
                                                               c01 * torque.x() + c11 * torque.y() + c12 * torque.z(),
                                                               c02 * torque.x() + c12 * torque.y() + minor2 * torque.z());
        if (step.allFinite() && step.squaredNorm() < 0.25) {
            newton = true;
            return step;
        }
    }
    return torque / (std::abs(trace) + 1e-9 * scale + 1e-300);
}

// The quaternion of a turn by rotation vector `step` (rad), of squared angle `angle2`; below
// 0.05 rad by its series (relative error under 1e-9), which spares the square root, sine and
// cosine. The series' result is unit to that error; extractRotation renormalises at the end.
Eigen::Quaterniond turnBy(const Eigen::Vector3d& step, double angle2) {
    if (angle2 >= 0.05 * 0.05) {
        const double angle = std::sqrt(angle2);
        return Eigen::Quaterniond(Eigen::AngleAxisd(angle, step / angle));
    }
    const Eigen::Vector3d v = (0.5 - angle2 / 48.0) * step; // sin(θ/2)/θ ≈ 1/2 − θ²/48
    return Eigen::Quaterniond(1.0 - angle2 / 8.0 + angle2 * angle2 / 384.0, v.x(), v.y(), v.z());
}

// q / |q| for |q|² = 1 + ε, |ε| ≪ 1: one Newton step of the inverse square root, exact to ε²,
// without a square root or a division.
Eigen::Quaterniond renormalised(const Eigen::Quaterniond& q) {
    return Eigen::Quaterniond((1.5 - 0.5 * q.squaredNorm()) * q.coeffs());
}

} // namespace

Eigen::Quaterniond extractRotation(const Eigen::Matrix3d& A, Eigen::Quaterniond q, int maxIterations,
                                   double tolerance, double newtonStop) {
    q.normalize(); // the warm start may be off unit by more than renormalised() repairs
    for (int iteration = 0; iteration < maxIterations; ++iteration) {
        bool newton = false;
        const Eigen::Vector3d step = fitStep(q.toRotationMatrix().transpose() * A, newton);
        const double angle2 = step.squaredNorm();
        if (!(angle2 > tolerance * tolerance)) break; // also stops on NaN
        // Kept unit to ~1e-18 each turn, so toRotationMatrix() stays a rotation.
        q = renormalised(q * turnBy(step, angle2));
        // A Newton step θ leaves an error of order θ²: after one under newtonStop the fit is
        // done (warm-started fits mostly end here, after one evaluation instead of two).
        if (newton && angle2 < newtonStop * newtonStop) break;
    }
    return q;
}

} // namespace shatter::oriented
