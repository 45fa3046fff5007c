#pragma once
// Which fragments take over a joint (source 000 §3.6, last paragraph): every fragment that
// intersects the volume of the old joint's box gets a copy of the joint. Plain geometry in the
// mesh coordinates that the parent, its fragments and the box share.
#include <shatter/plugin/geometry/PhysicalMesh.h>

#include <vector>

namespace shatter {

// Indices (ascending) of the fragments with a primitive at most `tolerance` (m) from the box:
// the tolerance the joint's attachments were found with (the mesh's contact tolerance), since
// a joint box usually touches its body's surface rather than overlapping it.
std::vector<int> fragmentsTouchingBox(const std::vector<geometry::PhysicalMesh>& fragments,
                                      const geometry::JointBox& box, double tolerance);

} // namespace shatter
