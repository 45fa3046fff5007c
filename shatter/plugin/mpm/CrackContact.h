#pragma once
// Crack-surface contact (§3.1.3 of 001, after Guo & Nairn 2006): where the two surfaces of a
// crack meet at a node, their normal velocities are set to the centre-of-mass value, so the
// faces cannot pass through each other while they may still slide (frictionless).
#include <shatter/plugin/mpm/SimulationState.h>

namespace shatter::mpm {

// The two fields of a node that hold the material above and below a crack: (1, 2) when both
// exist, else (1, 0) or (0, 2); false when the node does not straddle a crack.
bool crackFieldPair(const Grid& g, size_t node, int& above, int& below);

// Applies eqs. 7-10 at node i if it straddles a crack: contact when the surfaces approach,
// (v_a − v_b)·n < 0, and have closed, (u_a − u_b)·n < 0, with n the node's averaged crack
// normal (pointing to the "above" side) and u the mass-weighted nodal displacements. Called
// for every node by the grid pass (GridUpdate.h).
void crackContactAtNode(Grid& g, size_t i);

} // namespace shatter::mpm
