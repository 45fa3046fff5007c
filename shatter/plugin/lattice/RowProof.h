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

// The "breaks decided" proof's part of the rows a region's CG leaves alone (rows with skip_k = 0).
struct OutsideProof {
    double scaled = 0.0;    // Σ r_k² / d_k, added in row order
    double squared = 0.0;   // Σ r_k², added in row order
    double room = INFINITY; // min of the distance to the break range's nearer end × √d_k
    bool beyond = false;    // some λ beyond its break range
};

// ConstraintSystem::outsideOf's pass over `rows` rows: the values of the plain loop
//     if (skip_k) continue;
//     scaled += r_k² / d_k;  squared += r_k²;
//     room = std::min(room, std::min(|x_k − breakLower_k|, |breakUpper_k − x_k|) · root_k);
//     beyond = beyond || x_k < breakLower_k || x_k > breakUpper_k
// a packet of rows at a time, as rowProof, without a branch per row: a skipped row adds +0 to
// the sums (which start at +0 and whose terms are all ≥ +0 or NaN, so adding +0 changes no
// bit), a NaN to the minimum (which std::min, and so Eigen's pmin, passes over as it does a
// NaN distance) and nothing to `beyond`. `room` as rowProof's: up to the sign of a zero.
OutsideProof outsideProof(size_t rows, const char* skip, const double* r, const double* x, const double* d,
                          const double* root, const double* breakLower, const double* breakUpper);

} // namespace shatter::lattice
