#pragma once
// Which fragments take over a joint (source 000 §3.6, last paragraph): every fragment that
// intersects the volume of the old joint's box gets a copy of the joint. Plain geometry in the
// mesh coordinates that the parent, its fragments and the box share.
#include <shatter/plugin/geometry/PhysicalMesh.h>

#include <vector>

namespace shatter {

class SystemContext;
class VisualBody;

// Indices (ascending) of the fragments with a primitive at most `tolerance` (m) from the box:
// the tolerance the joint's attachments were found with (the mesh's contact tolerance), since
// a joint box usually touches its body's surface rather than overlapping it.
std::vector<int> fragmentsTouchingBox(const std::vector<geometry::PhysicalMesh>& fragments,
                                      const geometry::JointBox& box, double tolerance);
// The same over meshes held elsewhere (e.g. moved into the bodies made of them).
std::vector<int> fragmentsTouchingBox(const std::vector<const geometry::PhysicalMesh*>& fragments,
                                      const geometry::JointBox& box, double tolerance);

// Copies every joint of `parent` that is not broken (same box, type and frame) to each of
// `bodies` whose mesh (meshes[k], in the parent's mesh coordinates) touches the joint's box,
// to the same other body, with a JointRecreated event each (joint = the copy, body = the new
// body, count = the old joint's id). The old joints stay with the parent. Returns the copies made.
int transferJoints(SystemContext& context, VisualBody& parent, const std::vector<VisualBody*>& bodies,
                   const std::vector<geometry::PhysicalMesh>& meshes);
int transferJoints(SystemContext& context, VisualBody& parent, const std::vector<VisualBody*>& bodies,
                   const std::vector<const geometry::PhysicalMesh*>& meshes);

} // namespace shatter
