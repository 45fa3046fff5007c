#pragma once
// The rotational part of a 3×3 moment matrix, as a unit quaternion (source 000 §3.2.1).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <shatter/plugin/oriented/SimdLanes.h>

#include <span>

namespace shatter::oriented {

// Rotation R that maximises trace(Rᵀ A), found iteratively in the manner of Müller, Bender,
// Chentanez and Macklin, "A robust method to extract the rotational part of deformations"
// (MIG 2016): rotate q by a step along the torque-like vector Σ_k R e_k × A e_k until it
// vanishes. Their step τ/|trace RᵀA| converges linearly (by 1/3 per iteration for an
// isotropic A); near the answer a Newton step is taken instead, which converges quadratically
// (see RotationExtraction.cpp). Starts from `q` (warm start) and returns the updated quaternion. Unlike a polar
// decomposition it never returns a reflection, stays finite for a rank-deficient A (one
// point, collinear or coplanar points: the free directions keep the warm start's
// orientation), and needs one or two iterations when A changed little since the last call.
// Stops after `maxIterations`, when the rotation step falls below `tolerance` (rad), or
// after a Newton step under `newtonStop` (rad): the error it leaves is of order its square,
// below rounding for the default 1e-8.
Eigen::Quaterniond extractRotation(const Eigen::Matrix3d& A, Eigen::Quaterniond q, int maxIterations = 20,
                                   double tolerance = 1e-12, double newtonStop = 1e-8);

// How many fits extractRotations runs at once.
inline constexpr int kRotationLanes = 4;

// extractRotation(A[l], q[l], …) for l < q.size() (A as long: shatter::InputError otherwise), kRotationLanes independent
// fits at a time, each answer in q[l], bit for bit extractRotation's. Each fit is a chain of dependent
// operations (latency-bound, about a fifth of a soft sheet's frame); run as interleaved lanes
// (struct of arrays, every operation for all lanes before the next) the chains overlap, and
// the lanes' arithmetic shares SIMD instructions (4 lanes: two SSE2 or one AVX2 instruction,
// `path`; the same bits on both, shatter::InputError for a path this processor lacks). A batch
// takes as many iterations as its slowest fit; a fit that has stopped is left as it is.
void extractRotations(std::span<const Eigen::Matrix3d> A, std::span<Eigen::Quaterniond> q, int maxIterations,
                      double tolerance, double newtonStop, SimdPath path = fastestSimdPath());

} // namespace shatter::oriented
