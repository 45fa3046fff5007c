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
    VertexWelder() = default; // for no primitives (a body's, until it is built for them)
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
    // Whether a primitive's vertex carries visual id `id` (weld() writes exactly these ids).
    bool carries(int id) const {
        return id >= 0 && size_t(id) < referencePrimitive_.size() && referencePrimitive_[size_t(id)] >= 0;
    }
    // The visual ids no primitive carries (those weld() leaves alone), each once, in no
    // particular order. Kept up to date by fillHoles and removePrimitives, so that a fracture's
    // rest finds them without asking carries() of every visual id (16k of the 16k shell, ~1 M
    // instructions in five breaks).
    const std::vector<int>& uncarried() const { return uncarried_; }

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

    // Follows a removal where the primitives `removed` (ascending, distinct) go and the others
    // close up in order (VisualBody::removePrimitives); `primitives` are those left (read only
    // when the welder compacts itself). The visual id count stays. The welder is then the one
    // VertexWelder(primitives, visual id count) builds (the same count and reference vertex per
    // id), so weld() gives the same bits. Cost O(ids of the removed primitives + carriers of
    // those ids) plus a pass of integer copies over the survivors' entries and the visual ids,
    // where a new welder reads every primitive's ids (51 M instructions over three shrinks of
    // the 55k-tet Spot statue); the entries of removed primitives stay, dead, until they
    // outnumber the live ones (then a rebuild, paid for by the removals before it).
    // std::invalid_argument for indices that are not ascending primitive indices, or primitives
    // of the wrong count.
    void removePrimitives(const std::vector<ConvexPolyhedron>& primitives, const std::vector<int>& removed);
    // Writes positions[id] as weld(primitives, transform, positions) would, bit for bit, for
    // each id that the primitives `only` (ascending, distinct) carry and no other primitive
    // does (the ids a removal of them leaves to no primitive), and nothing else (`positions`
    // grows to the visual id count if shorter). Cost O(ids of `only` + carriers of those ids),
    // plus one zeroed mark per visual id.
    void weldCarriedOnlyBy(const std::vector<ConvexPolyhedron>& primitives, const std::vector<int>& only,
                           const Eigen::Isometry3d& transform, std::vector<Eigen::Vector3d>& positions) const;

private:
    // Checks that `indices` are ascending primitive indices (std::invalid_argument naming `what`).
    void checkAscending(const std::vector<int>& indices, const char* what) const;
    // The weld itself; vertex(p, k) gives vertex k of primitive p in the constructor's layout.
    template <class VertexAt>
    void average(const VertexAt& vertex, const Eigen::Isometry3d& transform,
                 std::vector<Eigen::Vector3d>& positions) const;
    // The constructor's blocks: every primitive's ids as flat entries (`flat` of them), each
    // at the head of its id's list, counted, and the first carrier of each visual id noted.
    void writeBlocks(const std::vector<ConvexPolyhedron>& primitives, size_t flat);
    // Appends primitive p's ids as a block of flat entries, each at the head of its id's list.
    void appendBlock(int p, const std::vector<int>& ids);
    // Count and reference vertex of visual id `id` from its list (dropping dead entries).
    void recount(int id);
    // uncarried_ after the visual ids `recounted` (each once; recountedMark[id] != 0 for exactly
    // these, below the visual id count) were counted again: the other entries stay.
    void relistUncarried(const std::vector<int>& recounted, const std::vector<char>& recountedMark);

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
    std::vector<int> uncarried_;          // the visual ids whose referencePrimitive_ is -1 (uncarried())
};

} // namespace shatter::geometry
