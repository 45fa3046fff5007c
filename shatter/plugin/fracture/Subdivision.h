#pragma once
// Adaptive subdivision (source 000 §3.6, the ductile variant of fracture): the pattern placed
// at an impact cuts the primitives near it exactly as a brittle fracture would, but the pieces
// stay one body. A coarse mesh gets fine primitives where it was hit, so a plastic dent
// computed afterwards has detail there (the source's metal door, Fig. 7). The cut is made in
// the rest configuration: vertices at the same rest position share one global id, and the
// visual surface is the body's own surface, re-tiled where it was cut (no crack face: nothing
// separates).
#include <shatter/plugin/fracture/FractureMesh.h>

#include <vector>

namespace shatter::fracture {

struct SubdivisionResult {
    // The subdivided body, in the body's rest coordinates. Its primitives: first the body's
    // primitives that were not cut, in the body's order (`kept` of them), then the pieces of
    // the cut ones, by body primitive (a primitive's pieces consecutive): a caller can keep
    // what it built for the first ones and build only the rest. Visual ids
    // 0 .. body.visual.positions.size()-1 are the body's visual vertices, at their positions;
    // the new visual vertices follow, then the inner (extruded) ids. Visual faces of primitives
    // that were not cut are the body's faces (a new vertex on one of their edges is inserted
    // into the polygon, so the surface has no T-junction); where a primitive was cut, its face
    // is replaced by the pieces' faces on it, in the same place of the face list. Crack-face
    // flags carry over (the pieces of a cut closed convex part take its first face's flag);
    // the subdivision makes no crack face of its own.
    geometry::PhysicalMesh mesh;
    // Per primitive of `mesh`: the body primitive it came from, and whether it was cut (false:
    // the body's primitive, its geometry bit for bit, only its ids renumbered).
    std::vector<int> parents;
    std::vector<bool> clipped;
    int kept = 0;
    // Body primitives that were cut (0: `mesh` is the body, nothing changed).
    int primitivesCut = 0;
    // Wall-clock seconds: the cut (cutMesh: placement and cutting) and the re-assembly as one body.
    double cutSeconds = 0.0, assemblySeconds = 0.0;
};

// Cuts `body` by the cells of `pattern` within its radius placed at `where` (as fractureMesh
// does) and keeps every piece in the one body. Connections are kept between primitives that
// were not cut and recomputed (GJK within the body's contact tolerance) only among the pieces
// of a cut primitive and its connected neighbours, so a connected body stays connected.
// Mass and volume are the body's up to round-off. Throws shatter::InputError naming the body
// for what fractureMesh rejects. Same input ⇒ same bits.
SubdivisionResult subdivideMesh(const geometry::PhysicalMesh& body, const FracturePattern& pattern,
                                const Placement& where, const CutSettings& settings);

} // namespace shatter::fracture
