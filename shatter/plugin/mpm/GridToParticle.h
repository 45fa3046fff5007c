#pragma once
// The particle stages (§3.1.5-3.1.6 of 001): gather velocity (PIC, eq. 18, or APIC) and
// velocity gradient from each particle's own fields (eq. 12), update F_E (eq. 13) with the
// snow return mapping (eqs. 14-17), collide particles, and move them (eq. 19). Also
// leaves what the next substep needs: each particle's stress (s.stress, for the scatter),
// s.fastestSignal (for the CFL condition), s.particleBounds (for the grid) and
// s.chunkBounds (for its own collider test).
#include <shatter/plugin/mpm/SimulationState.h>

namespace shatter::mpm {

// Needs updateAfterParticleEdit to have run since the particles were last seeded or edited.
void gridToParticles(SimulationState& s, double dt);

// Sizes the per-particle arrays of s (stress, external forces) and computes s.stress,
// s.fastestSignal, s.particleBounds and s.chunkBounds from the particles as they are: after
// seeding, or after the application edited them.
void updateAfterParticleEdit(SimulationState& s);

} // namespace shatter::mpm
