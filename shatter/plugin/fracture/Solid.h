#pragma once
// A convex solid while it is being cut: vertices with their global ids, polygon faces in
// one flat list, and per face what it shows (source 000 §3.4, §3.6).
#include <shatter/plugin/geometry/ConvexPolyhedron.h>

#include <cstdint>
#include <memory>
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

// The faces, kinds and ids of every cut piece of a fracture, one piece after another in
// blocks that never move (a thousand pieces a break, where a Solid each cost five
// allocations, a copy and five frees); their positions live in their polyhedra.
class CutFaceStore {
public:
    // Keeps the solid's faces, kinds and ids; returns the piece's index (0, 1, ...).
    int add(const Solid& solid);
    CutFaces operator[](int piece) const;

private:
    // Copies into blocks of at least kBlock values, a new block when the current one has no
    // room: growing one vector per list moved everything added so far at each doubling
    // (~0.26 MB a 64-cell break of the 16k shell, ~1.3 M instructions in five, and ~70
    // allocations a break).
    template <typename T>
    class Blocks {
    public:
        T* take(size_t n);

    private:
        static constexpr size_t kBlock = 16384;
        std::vector<std::unique_ptr<T[]>> blocks_;
        T* next_ = nullptr;
        size_t left_ = 0;
    };
    struct Piece {
        const int* ints;        // faceStart (faces + 1, from 0), then faceVertices, then ids
        const FaceKind* kinds;
        int faces, vertices, ids; // face count, faceVertices' and ids' sizes
    };
    Blocks<int> ints_;
    Blocks<FaceKind> kinds_;
    std::vector<Piece> pieces_;
};

// The primitive as a solid; a face is Visual when all its ids are below visualVertexCount.
// shapeOfPrimitive leaves every face Hidden, for a caller that knows what each shows.
void shapeOfPrimitive(const geometry::ConvexPolyhedron& primitive, Solid& out);
void solidOfPrimitive(const geometry::ConvexPolyhedron& primitive, int visualVertexCount, Solid& out);
FaceKind kindOfFace(const geometry::ConvexPolyhedron& primitive, int face, int visualVertexCount);

// The piece as a polyhedron (no validity checks: the clipper keeps it closed and convex).
geometry::ConvexPolyhedron polyhedronOf(const Solid& solid);

} // namespace shatter::fracture
