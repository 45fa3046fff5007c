#pragma once
// The J-integral around a crack tip (§3.1.8 of 001, after Guo & Nairn 2004, 2006).
//
// The contour is a circle of radius r (2 cells) around the tip, from the point where the
// crack leaves the circle on its lower face, counter-clockwise through the material ahead
// of the tip, to the same point on its upper face, in `segments` (16) equal arcs. Particle
// values are carried to the contour points from the correct side of the crack only: a
// particle counts for a contour point when the straight line between them crosses no crack
// (the line-crossing test of the transfers).
//
// Three deliberate departures from the source, all for accuracy (measured in the tests):
//  - the transfer to a contour point is a mass- and B-spline-weighted least-squares fit of
//    a quadratic polynomial (moving least squares) rather than a weighted mean (eq. 25).
//    A mean is biased to first order where the data are one-sided (the contour's ends on
//    the crack faces) and to second order everywhere; the quadratic fit is exact for
//    fields up to second degree, on one side or both. It falls back to a linear fit and
//    then to the mean where too few particles are around.
//  - the integral over the contour uses Simpson's rule on the 17 points instead of the
//    trapezoid rule (eq. 27): the integrand is smooth in the angle, so the error falls from
//    O(h²) to O(h⁴) for the same points.
//  - the modes are split by interaction integrals (below), not by the crack opening.
#include <shatter/plugin/mpm/LineCrossing.h>
#include <shatter/plugin/mpm/Types.h>

#include <vector>

namespace shatter::mpm {

// What the J-integral needs of one particle, in the current configuration.
struct NearTipSample {
    Vec2 x;
    double mass = 0;
    double volume = 0;     // reference area, m²
    Mat2 sigma;            // Cauchy stress, Pa
    Mat2 gradU;            // displacement gradient ∂u_i/∂x_j (F − I)
    double W = 0;          // stored energy density, J/m³
    double kinetic = 0;    // kinetic energy density ½ρv², J/m³
};

struct ContourSettings {
    double radius = 0;    // m (2 cells)
    int segments = 16;    // even, for Simpson's rule
    double dx = 0;        // cell size: the width of the transfer kernel
    // Elastic constants at the tip for the interaction integrals' auxiliary fields (> 0):
    // shear modulus μ and Kolosov's κ (Material::kolosov).
    double shearModulus = 0;
    double kappa = 0;
};

struct JIntegralResult {
    bool valid = false;   // false: the crack does not leave the circle, or the contour leaves the body
    double J = 0;         // along the tip direction, J/m²
    Vec2 Jvector = Vec2::Zero(); // (J_x, J_y) of eq. 27
    // K_I and K_II from the interaction integrals (Yau, Wang & Corten 1980) with Williams'
    // near-tip fields of unit K_I and K_II as the auxiliary fields, on the same contour and
    // from the same transferred values, in the tip's frame (static terms):
    //   M = ∫ [σ:ε_aux n_x − (σ n)·∂u_aux/∂x − (σ_aux n)·∂u/∂x] ds,  K = M E'/2.
    // Linear in the actual field: a part of it that is not a K field (noise, the regular
    // fields of a finite body) enters only through its overlap with the auxiliary field.
    // Used for the mode mixity (StressIntensity.h).
    double KIinteraction = 0, KIIinteraction = 0;
    std::vector<Vec2> contour;
};

// Where the crack, walking back from tip `tip` (0: first point, 1: last), first leaves the
// circle of `radius` around it; false when it never does (the crack is shorter).
bool contourCrackCrossing(const std::vector<Vec2>& points, int tip, double radius, Vec2& crossing);

// J at `tipPosition` for a crack growing along unit `direction`; `crossing` is where the
// crack leaves the contour circle; `segments` are all cracks (for the side test).
JIntegralResult jIntegral(const std::vector<NearTipSample>& particles, const Vec2& tipPosition,
                          const Vec2& direction, const Vec2& crossing, const CrackSegments& segments,
                          const ContourSettings& settings);

} // namespace shatter::mpm
