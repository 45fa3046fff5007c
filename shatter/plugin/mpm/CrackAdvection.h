#pragma once
// Crack particles move with the material (§3.1.7 of 001): with the nodes' centre-of-mass
// velocity over all fields (eqs. 20-22); the two crack surfaces are tracked as displacements
// moved with the velocity field of the material on each side (eqs. 23-24).
#include <shatter/plugin/mpm/SimulationState.h>

namespace shatter::mpm {

// Uses the grid velocities of this substep; call after gridToParticles and before the
// crack geometry changes.
void advectCracks(SimulationState& s, double dt);

// Unit left normal of the polyline at point k (mean of its segments' normals).
Vec2 crackPointNormal(const Crack& c, size_t k);

} // namespace shatter::mpm
