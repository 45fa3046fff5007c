#pragma once
// Stress intensity factors. The solver takes the magnitude from J (K_I² + K_II² = E' J) and
// the mode mixity from the interaction integrals (stressIntensityFromInteraction;
// JIntegral.h). Before, the mixity came from the parts of J in the fields' symmetric and
// antisymmetric halves, K_II = √(E' J_II): J_II is quadratic in the antisymmetric field, so
// noise of either sign in it (0.5% of J behind a running crack) read as |K_II|/K_I = √0.005
// = 7% of one sign or as exactly 0 of the other, and a running crack kinked on noise (issue
// 20: 0.14-0.19 rad kinks a crack line 1/3 cell off the grid lines; the interaction integral
// read 0.3-2.3% there, of the opposite sign). The source's split by the crack opening behind
// the tip (eqs. 31-32 of 001) is kept for reference; it reads the displacement jump within
// two cells of the tip, where the discrete field is least accurate: on the 45° crack with
// exact boundary tractions (validation/InclinedCrack.h) the sliding jump there was 20-37%
// too large while it was 6% too large mid-crack and the opening was right to 1%, so the
// opening ratio gave K_II/K_I 1.26-1.33 where J and its modes gave 1.04. The source's:
//   K_I = (δ_I/δ)·√(J E'),  K_II = (δ_II/δ)·√(J E'),  δ = |(δ_I, δ_II)|,
// E' = E (plane stress) or E/(1 − ν²) (plane strain). Near a tip both opening components
// grow as √s with the distance s behind it, in the ratio K_II/K_I (LEFM), so the ratio is
// measured by a least-squares fit δ(s) = c·√s over all crack particles within the J contour
// rather than read at one particle: that averages out particle-scale noise.
#include <shatter/plugin/mpm/Crack.h>
#include <shatter/plugin/mpm/Types.h>

namespace shatter::mpm {

struct CrackOpening {
    double opening = 0; // δ_I: normal separation of the faces (> 0: open)
    double sliding = 0; // δ_II: tangential, upper face relative to lower along the growth direction
    bool valid = false; // false without any crack particle within range
};

// Fit coefficients c_I, c_II of δ = c·√s over crack particles at arc length (0, range]
// behind tip `tip`, in the tip's frame (upper face = left of the growth direction).
CrackOpening crackOpeningNearTip(const Crack& crack, int tip, double range);

struct StressIntensity {
    double KI = 0, KII = 0; // Pa·√m
};

// From J (J/m²) and the opening; a closed or unknown opening is read as pure mode I.
StressIntensity stressIntensity(double J, const CrackOpening& opening, double effectiveModulus);

// From J and the interaction integrals' K_I^M, K_II^M (JIntegral.h): the mixity angle
// ψ = atan2(K_II^M, K_I^M), K_I = √(E' J)·cos ψ, K_II = √(E' J)·sin ψ. Without J > 0, zero.
StressIntensity stressIntensityFromInteraction(double J, double KIinteraction, double KIIinteraction,
                                               double effectiveModulus);

} // namespace shatter::mpm
