#pragma once
// The exact linear-elastic field of a straight crack of length 2a in an infinite plate
// (Westergaard 1939): remote biaxial tension σ (mode I, K_I = σ√(πa)) plus remote shear τ
// (mode II, K_II = τ√(πa)), with the stress function Z = s·z/√(z² − a²), z = x + iy in the
// crack's frame (crack on the x-axis from −a to a). Both fields satisfy equilibrium,
// compatibility and traction-free faces exactly, so J = (K_I² + K_II²)/E' on every contour:
// the reference the J-integral routine is validated against.
#include <shatter/plugin/mpm/Material.h>
#include <shatter/plugin/mpm/Types.h>

namespace shatter::mpm {

struct WestergaardField {
    double a = 1;        // half crack length, m
    double sigma = 0;    // remote biaxial tension, Pa
    double tau = 0;      // remote shear, Pa
    double E = 1, nu = 0.3;
    Analysis analysis = Analysis::PlaneStress;

    struct State {
        Mat2 stress;     // Pa
        Vec2 u;          // displacement, m
        Mat2 gradU;      // ∂u_i/∂x_j
    };
    // At (x, y) in the crack frame; y = ±0 on the faces is selected by the sign of `y`
    // (pass ±tiny values). Undefined on the crack line itself and at the tips.
    State at(double x, double y) const;

    double KI() const;
    double KII() const;
};

} // namespace shatter::mpm
