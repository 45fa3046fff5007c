#pragma once
// The particle stages (§3.1.5-3.1.6 of 001): gather velocity (PIC, eq. 18, or APIC) and
// velocity gradient from each particle's own fields (eq. 12), update F_E (eq. 13) with the
// snow return mapping (eqs. 14-17), collide particles, and move them (eq. 19). Also
// leaves what the next substep needs: each particle's stress (s.stress, for the scatter),
// s.fastestSignal (for the CFL condition) and s.particleBounds (for the grid).
#include "plugin/mpm/SimulationState.h"

namespace shatter::mpm {

void gridToParticles(SimulationState& s, double dt);

// Computes s.stress, s.fastestSignal and s.particleBounds from the particles as they are:
// after seeding, or after the application edited them.
void updateAfterParticleEdit(SimulationState& s);

} // namespace shatter::mpm
