#pragma once
// The render surface of a body (source 000 §3.4): polygon faces over vertices whose
// positions are the averages of the primitive vertices that carry the same global id.
#include <shatter/plugin/geometry/ConvexPolyhedron.h>

#include <Eigen/Core>
#include <span>
#include <vector>

namespace shatter::geometry {

struct VisualMesh {
    std::vector<Eigen::Vector3d> positions;  // one per visual vertex (= global id)
    std::vector<std::vector<int>> faces;     // polygons, counter-clockwise from outside
    // Per face: true where fracture opened the surface inside the original solid (a crack
    // face, drawn with its own material). Empty when the mesh has no crack face.
    std::vector<bool> crackFace;

    bool isCrackFace(size_t face) const { return face < crackFace.size() && crackFace[face]; }
};

// Averages primitive vertex positions per global id (source 000 §3.4). Writes
// positions[id] for every id in [0, positions.size()) that some primitive vertex
// carries; ids >= positions.size() (inner vertices of extruded faces) are ignored.
// `transform` maps primitive coordinates to the output frame.
// weld() resizes `positions` to visualVertexCount and leaves ids no primitive carries
// untouched. The average is taken relative to the first vertex carrying each id, so
// vertices that coincide (a mesh at rest) weld to exactly their common position. The
// primitives passed to weld() must have the counts of those given to the constructor
// (std::invalid_argument otherwise). Cost: O(primitive vertices), no allocation.
class VertexWelder {
public:
    VertexWelder(const std::vector<ConvexPolyhedron>& primitives, int visualVertexCount);
    void weld(const std::vector<ConvexPolyhedron>& primitives, const Eigen::Isometry3d& transform,
              std::vector<Eigen::Vector3d>& positions) const;
    // Same, with the vertex positions given directly (a deforming solver), flat: primitive
    // after primitive, each one's vertices in order (one array, not one per primitive).
    void weld(std::span<const Eigen::Vector3d> flatVertices, const Eigen::Isometry3d& transform,
              std::vector<Eigen::Vector3d>& positions) const;
    // Ascending indices of the primitives it was built for that carry an id `i` with
    // `ids[i] != 0` (ids past the end of `ids` count as 0). It reads its own flat id list in
    // order: asking each primitive for its ids reads one scattered heap block per primitive,
    // which perf showed as most of a 16k-primitive fracture rest's edit (RemainderEdit.h).
    std::vector<int> primitivesCarrying(const std::vector<char>& ids) const;

private:
    // The weld itself; vertex(p, k) gives vertex k of primitive p in the constructor's layout.
    template <class VertexAt>
    void average(const VertexAt& vertex, const Eigen::Isometry3d& transform,
                 std::vector<Eigen::Vector3d>& positions) const;

    std::vector<double> inverseCount_; // per visual id: 1 / number of primitive vertices with it
    std::vector<int> vertexOffset_;    // per primitive: index of its first vertex in the flat layout (+ total)
    std::vector<int> flatIds_;         // per primitive vertex (flat): its global id
    std::vector<int> referencePrimitive_; // per visual id: primitive of the first vertex carrying it, or -1
    std::vector<int> referenceVertex_;    // per visual id: that vertex's index in its primitive
};

} // namespace shatter::geometry
