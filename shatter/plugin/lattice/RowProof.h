#pragma once
// The constraint solver's proof sums over every row (SafeRange), a packet of rows at a time.
#include <shatter/plugin/lattice/ConstraintSolver.h>

#include <cmath>
#include <cstddef>

namespace shatter::lattice {

struct RowProof {
    double scaled = 0.0;    // ‖D^-½ r‖² = Σ r_k² / d_k, added in row order
    double room = INFINITY; // min over rows of slack_k √d_k (slack: λ's distance to the nearer end of the safe range)
    bool beyond = false;    // some λ beyond its break range (false when `safe` has none)
};

// ConstraintSystem::proven's pass over `rows` rows of residual r, λ x, diagonal d and its root:
// the values of the plain loop
//     scaled += r_k² / d_k;  room = std::min(room, std::min(x_k − lower_k, upper_k − x_k) · root_k);
//     beyond = beyond || x_k < breakLower_k || x_k > breakUpper_k
// with a third fewer instructions (2 rows a packet with SSE2): each row's term, slack and tests
// are those operations lane by lane (Eigen's pmin(a, b) is std::min(a, b), NaN and ties
// included), and the terms are added to the sum one row after another in row order, so
// `scaled` and `beyond` have the loop's bits. The minimum is taken per lane, then over the
// lanes: it differs from the loop's only in the sign of a zero (a tie of +0 and −0), which the
// proof only compares (room > 0, reach < room), where ±0 are equal.
RowProof rowProof(size_t rows, const double* r, const double* x, const double* d, const double* root,
                  const SafeRange& safe);

} // namespace shatter::lattice
