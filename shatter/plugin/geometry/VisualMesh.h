#pragma once
// The render surface of a body (source 000 §3.4): polygon faces over vertices whose
// positions are the averages of the primitive vertices that carry the same global id.
#include <shatter/plugin/geometry/ConvexPolyhedron.h>
#include <shatter/plugin/geometry/HoleFilling.h>

#include <Eigen/Core>
#include <span>
#include <utility>
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
    // Ascending indices of the primitives that carry one of `ids` (each listed once; ids no
    // primitive carries are skipped). It follows its per-id lists of carrying vertices:
    // O(carriers of `ids`) plus a byte of flags per primitive, where asking each primitive for
    // its ids reads one scattered heap block per primitive (RemainderEdit.h: the kept
    // primitives of a fracture's rest that carry a swapped id).
    std::vector<int> primitivesCarrying(const std::vector<int>& ids) const;

    // Follows the edit of a fracture's rest (fracture::applyRemainderEdit): the primitives
    // `removed` (ascending) go, the survivors slots.moves names move, the primitives at
    // slots.addedAt come (slots = fillHoles(old primitive count, removed, added count)), the
    // kept primitives' ids are exchanged pairwise by `idSwaps`, and the visual ids are now
    // [0, visualVertexCount). `primitives` are those after the edit (only the added ones are
    // read). The welder is then the one VertexWelder(primitives, visualVertexCount) builds:
    // the same count and reference vertex (the first carrier in primitive order) per id, so
    // weld() gives the same bits. Cost O(ids of the removed, moved and added primitives +
    // carriers of those ids, the swapped ids and the new visual ids + visual ids), where a
    // new welder reads every primitive's ids (3 M instructions of a 16k-primitive rest).
    void fillHoles(const std::vector<ConvexPolyhedron>& primitives, const std::vector<int>& removed,
                   const HoleFilling& slots, const std::vector<std::pair<int, int>>& idSwaps, int visualVertexCount);

private:
    // The weld itself; vertex(p, k) gives vertex k of primitive p in the constructor's layout.
    template <class VertexAt>
    void average(const VertexAt& vertex, const Eigen::Isometry3d& transform,
                 std::vector<Eigen::Vector3d>& positions) const;
    // Appends primitive p's ids as a block of flat entries, each at the head of its id's list.
    void appendBlock(int p, const std::vector<int>& ids);
    // Count and reference vertex of visual id `id` from its list (dropping dead entries).
    void recount(int id);

    std::vector<double> inverseCount_; // per visual id: 1 / number of primitive vertices with it
    std::vector<int> blockStart_;      // per primitive: index of its first vertex in the flat entries
    std::vector<int> blockSize_;       // per primitive: its vertex count
    // Per flat entry (a primitive vertex; entries of removed primitives are dead until the
    // next rebuild): its global id, its primitive (-1: dead), the next entry with the same id.
    std::vector<int> flatIds_;
    std::vector<int> flatOwner_;
    std::vector<int> nextCarrier_;
    std::vector<int> firstCarrier_;       // per global id: an entry carrying it, or -1
    int deadEntries_ = 0;
    std::vector<int> referencePrimitive_; // per visual id: primitive of the first vertex carrying it, or -1
    std::vector<int> referenceVertex_;    // per visual id: that vertex's index in its primitive
};

} // namespace shatter::geometry
