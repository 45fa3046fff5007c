#pragma once
// Step 1 of the source's order (§3.1.1-3.1.2 of 001): rebuild the grid around the particles
// and scatter mass, momentum, displacement and force into the velocity fields.
#include <shatter/plugin/mpm/SimulationState.h>

namespace shatter::mpm {

// Resizes the grid to the particles (plus the crack points) and clears it, sorts particles into
// stripes.
void prepareGrid(SimulationState& s);
// Mass, and momentum (APIC: with the affine term) plus the substep's impulse Δt·f with
// f = −V⁰ τ ∇w + w (f_ext + m g), τ the Kirchhoff stress of the current F_E, F_P; near cracks
// also the mass-weighted displacement (for crack contact). Needs prepareGrid and the field
// assignment (FieldAssignment::slot: −1 far from cracks, −2 near enough for displacement).
void particlesToGrid(SimulationState& s, double dt);

} // namespace shatter::mpm
