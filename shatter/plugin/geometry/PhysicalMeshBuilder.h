#pragma once
// The physical-mesh builder behind buildPhysicalMesh, for callers that can name each face
// better than by its index (the OBJ loader knows file and line).
#include <shatter/plugin/geometry/PhysicalMesh.h>

#include <string>
#include <vector>

namespace shatter::geometry {

// buildPhysicalMesh, with faceLabels[i] naming face i in messages (e.g. "door.obj:12");
// with no labels faces are named "face i". primitivesBefore: primitives of the file's
// bodies built before this one, counted against the same settings.maxPrimitives.
PhysicalMesh buildLabelledPhysicalMesh(const std::string& name, const std::vector<Eigen::Vector3d>& positions,
                                       const std::vector<std::vector<int>>& faces,
                                       const std::vector<std::string>& faceLabels,
                                       const PhysicalMeshSettings& settings, long long primitivesBefore);

} // namespace shatter::geometry
