#pragma once
// The render surface of a body (source 000 §3.4): polygon faces over vertices whose
// positions are the averages of the primitive vertices that carry the same global id.
#include "plugin/geometry/ConvexPolyhedron.h"

#include <Eigen/Core>
#include <vector>

namespace shatter::geometry {

struct VisualMesh {
    std::vector<Eigen::Vector3d> positions;  // one per visual vertex (= global id)
    std::vector<std::vector<int>> faces;     // polygons, counter-clockwise from outside
};

// Averages primitive vertex positions per global id (source 000 §3.4). Writes
// positions[id] for every id in [0, positions.size()) that some primitive vertex
// carries; ids >= positions.size() (inner vertices of extruded faces) are ignored.
// `transform` maps primitive coordinates to the output frame.
class VertexWelder {
public:
    VertexWelder(const std::vector<ConvexPolyhedron>& primitives, int visualVertexCount);
    void weld(const std::vector<ConvexPolyhedron>& primitives, const Eigen::Isometry3d& transform,
              std::vector<Eigen::Vector3d>& positions) const;
    // Same, with per-primitive vertex positions given directly (a deforming solver).
    void weld(const std::vector<std::vector<Eigen::Vector3d>>& primitiveVertices, const Eigen::Isometry3d& transform,
              std::vector<Eigen::Vector3d>& positions) const;

private:
    std::vector<double> inverseCount_; // per visual id: 1 / number of primitive vertices with it
};

} // namespace shatter::geometry
