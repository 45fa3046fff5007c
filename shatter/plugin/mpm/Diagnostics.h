#pragma once
// Whole-body sums used by the tests and the programs' summaries: mass, momentum, energy.
// Energies are per metre of thickness (J/m).
#include <shatter/plugin/mpm/Solver2D.h>

namespace shatter::mpm {

struct Totals {
    double mass = 0;
    Vec2 momentum = Vec2::Zero();
    double angularMomentum = 0;   // about the origin, particles' own plus APIC spin
    double kinetic = 0;           // ½ m v²
    double elastic = 0;           // Σ V⁰ W
    double gravitational = 0;     // −Σ m g·x (zero at the origin)
    Vec2 centreOfMass = Vec2::Zero();

    double total() const { return kinetic + elastic + gravitational; }
};

Totals totals(const Solver2D& solver);

// Sum of the masses on the grid of the last substep (all fields).
double gridMass(const Solver2D& solver);

} // namespace shatter::mpm
