#pragma once
// The grid stages between the two transfers (§3.1.2-3.1.4 of 001): velocities from momentum
// and force, viscous damping, fixed nodes, crack-surface contact and collisions with the
// colliders.
#include <shatter/plugin/mpm/SimulationState.h>

namespace shatter::mpm {

// All grid stages of a substep in the source's order: velocities v* = (momentum + Δt f)/m in
// every field (eq. 6) times exp(−c Δt) for damping c (nodes touched by a fixed particle held
// at rest, nodes without mass at zero), crack contact, collisions (eq. 11 with Coulomb
// friction, every field of every node inside a collider), crack contact again. Every stage
// acts on each node alone, so they run in one pass over the nodes (one parallel loop instead
// of four: fewer barriers, one sweep through memory) with the same result as the four stages
// one after the other. Nodes outside the band around the cracks (FieldAssignment::nodes)
// skip the crack stages, and rows of nodes no collider can reach skip the colliders.
void updateGrid(SimulationState& s, double dt);

} // namespace shatter::mpm
