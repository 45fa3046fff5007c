#pragma once
// A convex solid while it is being cut: vertices with their global ids, polygon faces in
// one flat list, and per face what it shows (source 000 §3.4, §3.6).
#include <shatter/plugin/geometry/ConvexPolyhedron.h>

#include <cstdint>
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

// The primitive as a solid; a face is Visual when all its ids are below visualVertexCount.
void solidOfPrimitive(const geometry::ConvexPolyhedron& primitive, int visualVertexCount, Solid& out);
FaceKind kindOfFace(const geometry::ConvexPolyhedron& primitive, int face, int visualVertexCount);

// The piece as a polyhedron (no validity checks: the clipper keeps it closed and convex),
// taking the solid's positions instead of copying them: `solid` is left without positions
// (a cut piece's solid is kept only for its faces, their kinds and its ids).
geometry::ConvexPolyhedron takePolyhedron(Solid& solid);

} // namespace shatter::fracture
