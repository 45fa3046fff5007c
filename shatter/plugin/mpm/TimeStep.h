#pragma once
// The adaptive substep: the CFL condition Δt = cfl·dx / max_p(c_p + |v_p|), with c_p the
// particle's dilatational wave speed including snow hardening (see waveSpeed).
// A scene therefore cannot explode because its user picked too large a step.
// The maximum is gathered while the particles are updated (gridToParticles), so that it
// costs no pass of its own; updateAfterParticleEdit() computes it from scratch.
#include <shatter/plugin/mpm/SimulationState.h>

#include <cmath>

namespace shatter::mpm {

// std::max silently drops a NaN; mapping it to +∞ lets the maximum report a blow-up.
inline double finiteOrInfinite(double v) { return std::isfinite(v) ? v : INFINITY; }

// The CFL step from s.fastestSignal, capped by time.max_step. Throws std::runtime_error when
// the state has become non-finite (a blow-up is reported, not propagated).
double stableTimeStep(const SimulationState& s);

} // namespace shatter::mpm
