#pragma once
// A proven lower bound on the smallest eigenvalue of a constraint system's Jacobi-scaled matrix
// Â = D^-½ A D^-½ (A = J M⁻¹ Jᵀ, D its diagonal). With it, a solve can stop as soon as the
// exact forces are proven to break and weaken nothing (ConstraintSystem::solve, SafeRange):
// |λ*_k - λ_k| ≤ ‖D^-½ r‖ / (μ √d_k) for the residual r of any λ.
//
// One bound serves every later system of the same lattice: a piece's system after breaks, or
// of a part cut from it, keeps a subset of the rows with the same entries (an entry depends only
// on the normals of its two links and the mass of the particle they share), so its Â is a
// principal submatrix of the first one's, whose smallest eigenvalue is no smaller (Cauchy
// interlacing). That holds for the system of a whole lattice with no broken link (a link joined
// again later is one of its rows) while no particle's mass or fixed flag changes.
#include <shatter/plugin/lattice/ConstraintSolver.h>

namespace shatter::lattice {

// μ > 0 with μ ≤ λ_min(Â), or 0 when none is found down to 2^-12 (a singular matrix: a
// cluster of free particles with more links than degrees of freedom, e.g. a tet whose four
// neighbours are all fixed). One sparse Cholesky factorisation per halving of the trial value:
// 7 G instructions (~0.55 s) for the 99,928 rows of the 55,411-tet Spot, nearly all in the one
// that succeeds, so it is done once, when the body is made.
double scaledEigenvalueLowerBound(const ConstraintSystem& system);

} // namespace shatter::lattice
