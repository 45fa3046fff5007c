#pragma once
// A convex solid while it is being cut: vertices with their global ids, polygon faces in
// one flat list, and per face what it shows (source 000 §3.4, §3.6).
#include <shatter/plugin/geometry/ConvexPolyhedron.h>

#include <cstdint>
#include <span>
#include <vector>

namespace shatter::fracture {

// What a face of a piece is on the fragment's surface.
enum class FaceKind : std::uint8_t {
    Visual, // part of the body's visual surface (all its vertices are visual vertices)
    Hidden, // inside the body's visual surface (the inner side or the rim of an extruded face)
    Crack,  // made by a cut
};

struct Solid {
    std::vector<Eigen::Vector3d> positions;
    std::vector<int> ids;
    std::vector<int> faceStart{0}; // face f is faceVertices[faceStart[f] .. faceStart[f + 1])
    std::vector<int> faceVertices;
    std::vector<FaceKind> kinds;

    int faceCount() const { return int(kinds.size()); }
    void clear();
    void addFace(FaceKind kind) { // after pushing its vertices to faceVertices
        faceStart.push_back(int(faceVertices.size()));
        kinds.push_back(kind);
    }
};

// A cut piece's faces as a fragment's surface reads them (views into CutFaceStore): face f's
// vertices are faceVertices[faceStart[f] .. faceStart[f + 1]), indices into ids (the piece's
// global vertex ids); kinds[f] is what face f shows.
struct CutFaces {
    std::span<const int> faceStart; // faceCount() + 1 entries
    std::span<const int> faceVertices;
    std::span<const FaceKind> kinds;
    std::span<const int> ids;
    int faceCount() const { return int(kinds.size()); }
};

// The faces, kinds and ids of every cut piece of a fracture, one piece after another in one
// set of buffers (a thousand pieces a break, where a Solid each cost five allocations, a
// copy and five frees); their positions live in their polyhedra.
class CutFaceStore {
public:
    // Keeps the solid's faces, kinds and ids; returns the piece's index (0, 1, ...).
    int add(const Solid& solid);
    CutFaces operator[](int piece) const;

private:
    std::vector<int> faceStart_{0}; // every piece's faces: face g is faceVertices_[faceStart_[g] .. faceStart_[g + 1])
    std::vector<int> faceVertices_; // indices into the piece's ids
    std::vector<FaceKind> kinds_;
    std::vector<int> ids_;
    std::vector<int> firstFace_{0}, firstId_{0}; // per piece, and one past the last
};

// The primitive as a solid; a face is Visual when all its ids are below visualVertexCount.
// shapeOfPrimitive leaves every face Hidden, for a caller that knows what each shows.
void shapeOfPrimitive(const geometry::ConvexPolyhedron& primitive, Solid& out);
void solidOfPrimitive(const geometry::ConvexPolyhedron& primitive, int visualVertexCount, Solid& out);
FaceKind kindOfFace(const geometry::ConvexPolyhedron& primitive, int face, int visualVertexCount);

// The piece as a polyhedron (no validity checks: the clipper keeps it closed and convex).
geometry::ConvexPolyhedron polyhedronOf(const Solid& solid);

} // namespace shatter::fracture
