#pragma once
// The J-integral routine alone, on particles that carry the exact Westergaard field
// (WestergaardField.h) around a crack in any position and orientation: what J, K_I and
// K_II does the routine return, against K_I = σ√(πa), K_II = τ√(πa)?
#include <shatter/plugin/mpm/Material.h>
#include <shatter/plugin/mpm/Types.h>

namespace shatter::mpm::validation {

struct ExactFieldCase {
    double a = 1;              // half crack length, m
    double sigma = 1e6;        // remote biaxial tension, Pa
    double tau = 0;            // remote shear, Pa
    double E = 3e9, nu = 0.3;
    Analysis analysis = Analysis::PlaneStress;
    double dx = 0.1;           // cell size; particles at dx/2, contour radius 2dx
    double angle = 0;          // crack direction, rad
    Vec2 centre = Vec2::Zero();
    int tip = 1;               // 0: the tip at −a (start), 1: at +a (end)
};

struct ExactFieldResult {
    double J = 0, KI = 0, KII = 0;                // computed
    double Jref = 0, KIref = 0, KIIref = 0;       // exact
    bool valid = false;
};

ExactFieldResult runExactFieldCase(const ExactFieldCase& c);

} // namespace shatter::mpm::validation
