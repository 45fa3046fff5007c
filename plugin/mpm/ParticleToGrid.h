#pragma once
// Step 1 of the source's order (§3.1.1-3.1.2 of 001): rebuild the grid around the particles
// and scatter mass, momentum, displacement and force into the velocity fields.
#include "plugin/mpm/SimulationState.h"

namespace shatter::mpm {

// Resizes the grid to the particles (plus the crack points), sorts particles into stripes.
void prepareGrid(SimulationState& s);
// Mass, momentum (APIC: with the affine term), mass-weighted displacement (for crack
// contact), and force: −V⁰ τ ∇w + w (f_ext + m g), τ the Kirchhoff stress of the current
// F_E, F_P. Needs prepareGrid and the field assignment.
void particlesToGrid(SimulationState& s);

} // namespace shatter::mpm
