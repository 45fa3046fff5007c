#pragma once
// The vector updates of one conjugate-gradient iteration after its step length, in one pass.
#include <Eigen/Core>

namespace shatter::lattice {

// ‖r‖² and rᵀz after the step.
struct StepSums {
    double residual = 0.0;       // rᵀr
    double preconditioned = 0.0; // rᵀz
};

// x += α p; r −= α Ap; z = D⁻¹ ∘ r; then ‖r‖² and r·z, with exactly the bits of those five
// Eigen expressions evaluated one after the other (`x += alpha * p; r -= alpha * ap;
// r.squaredNorm(); z = inverseDiagonal.cwiseProduct(r); r.dot(z)`), in one pass over the
// vectors instead of five: the element-wise values are the same products and sums, and the two
// sums are added in the order Eigen's reduction adds a dynamic vector (two packet accumulators
// over pairs of packets, then an odd packet, the packet's lanes, the odd elements).
// CG's region solves spent a third of their own instructions in those passes.
// p, ap, inverseDiagonal, x, r and z have one size; z is resized to it.
StepSums conjugateGradientStep(double alpha, const Eigen::VectorXd& p, const Eigen::VectorXd& ap,
                               const Eigen::VectorXd& inverseDiagonal, Eigen::VectorXd& x, Eigen::VectorXd& r,
                               Eigen::VectorXd& z);

} // namespace shatter::lattice
