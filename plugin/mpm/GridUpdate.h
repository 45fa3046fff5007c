#pragma once
// The grid stages between the two transfers (§3.1.2-3.1.4 of 001): velocities from momentum
// and force, viscous damping, fixed nodes, and collisions with the colliders.
#include "plugin/mpm/SimulationState.h"

namespace shatter::mpm {

// v* = (momentum + Δt f)/m in every field (eq. 6), times exp(−c Δt) for damping c; nodes
// touched by a fixed particle are held at rest. Nodes without mass get zero velocity.
void updateGridVelocities(SimulationState& s, double dt);

// Eq. 11 with Coulomb friction, for every field of every node inside a collider.
void collideGrid(SimulationState& s);

} // namespace shatter::mpm
