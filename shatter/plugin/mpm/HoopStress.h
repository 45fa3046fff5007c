#pragma once
// The maximum hoop stress criterion (Erdogan & Sih 1963; §3.1.9 of 001 with the corrected
// formulas of the source errata): a crack grows in the direction θ of maximum hoop stress,
//   θ = 2·atan((1 − √(1 + 8 (K_II/K_I)²)) / (4 K_II/K_I)),   (corrected eq. 33)
// opposite in sign to K_II (pure mode II: ∓70.53°), and it grows when
//   K_I cos³(θ/2) − 3/2 K_II cos(θ/2) sin θ ≥ K_c.            (corrected eq. 34)
namespace shatter::mpm {

// Kink angle in radians, relative to the current crack direction (counter-clockwise > 0).
// For K_I <= 0 (a closed crack) the pure mode II direction is returned.
double kinkAngle(double KI, double KII);

// The equivalent mode I intensity in direction θ (left side of eq. 34).
double effectiveStressIntensity(double KI, double KII, double theta);

} // namespace shatter::mpm
