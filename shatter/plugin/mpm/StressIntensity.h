#pragma once
// Stress intensity factors. The solver splits J into K_I and K_II with the mode parts of J
// (stressIntensityFromModes; JIntegral.h). The source's split by the crack opening behind
// the tip (eqs. 31-32 of 001) is kept for reference; it reads the displacement jump within
// two cells of the tip, where the discrete field is least accurate: on the 45° crack with
// exact boundary tractions (validation/InclinedCrack.h) the sliding jump there was 20-37%
// too large while it was 6% too large mid-crack and the opening was right to 1%, so the
// opening ratio gave K_II/K_I 1.26-1.33 where the mode parts of J give 1.04. The source's:
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

// From J and its mode I and II parts (JIntegral.h): K_I = s_I·√(E' J·J_I/(J_I + J_II)),
// K_II = s_II·√(E' J·J_II/(J_I + J_II)); parts below zero (noise) count as zero.
StressIntensity stressIntensityFromModes(double J, double JI, double JII, double signI, double signII,
                                         double effectiveModulus);

} // namespace shatter::mpm
