#pragma once
// Brittle fracture of a physical mesh by a fracture pattern placed at an impact (source 000
// §3.6, after Müller, Chentanez, Kim and Macklin 2013): every primitive that overlaps a cell
// within the pattern's radius is clipped by the cell's planes, the pieces of one cell form
// one fragment per connected component, and the rest of the body stays together (split into
// islands if the cut separated it). Everything happens in the body's rest coordinates.
#include <shatter/plugin/fracture/FracturePattern.h>
#include <shatter/plugin/fracture/Placement.h>
#include <shatter/plugin/fracture/PrimitiveIndex.h>
#include <shatter/plugin/fracture/RemainderEdit.h>
#include <shatter/plugin/geometry/PhysicalMesh.h>

#include <optional>
#include <string>
#include <vector>

namespace shatter::fracture {

struct CutSettings {
    // m. A fragment whose volume is below minimumPieceSize³ is not let loose on its own: it
    // joins the largest fragment one of its pieces touches (its neighbour across the cut).
    // Its pieces stay primitives of that fragment: nothing is ever dropped.
    double minimumPieceSize = 0.005;
    // m. A vertex within this distance of a cutting plane counts as on it: the cut passes
    // through the vertex, and no new vertex is made closer than this to a plane or to
    // another new vertex (new vertices within it share one global id).
    double snapTolerance = 1e-7;
    // Hand the rest of the body back as an edit of the body (FractureResult::remainderEdit)
    // instead of a new piece, when its visual surface is open (a closed surface shows its
    // inner side on every fragment, a change that is not local). The edit costs what the cut
    // touched; the piece costs a copy of the whole body.
    bool remainderInPlace = false;

    // Both positive and finite, the snap tolerance below the minimum piece size; errors name `body`.
    void check(const std::string& body) const;
};

struct FractureResult {
    // Each one connected island, in the body's rest (mesh) coordinates, with its own
    // primitives, connections, mass and visual mesh: the original surface inside it plus the
    // crack faces (flagged in visual.crackFace), welded by global id. Ids are renumbered per
    // piece (visual vertices first, as PhysicalMesh requires); sharedIds maps them back.
    std::vector<geometry::PhysicalMesh> pieces;
    // Per piece, per local global id: the fracture-wide id (the body's own ids for vertices
    // it had; new vertices numbered from body.globalIdCount up, one per rest position). Two
    // pieces' vertices with the same shared id are the same point of the rest shape.
    std::vector<std::vector<int>> sharedIds;
    // Per piece: the pattern cell it was cut free by, or -1 for an island of the rest.
    std::vector<int> cells;
    // Per piece: whether its convex hull overlaps no other piece (it may touch them), so that
    // it may collide as that hull. Proved, not measured: every primitive of the piece lies in
    // one cell within the radius (cells are convex and do not overlap, so the hull lies in the
    // cell too and everything outside the cell is clear of it), and the primitives of every
    // other piece in that cell lie beyond a plane from it (the plane normal to the line
    // between the two sets' vertex centroids). False for the rest's islands.
    std::vector<bool> hullIsClear;
    // Per piece, per primitive: the body primitive it came from, and whether it was clipped
    // (false: the primitive moved whole, its geometry bit for bit the body's).
    std::vector<std::vector<int>> parents;
    std::vector<std::vector<bool>> clipped;
    // Index of the piece holding the primitives outside the radius (the largest such island
    // by volume), or -1 when every primitive was cut free.
    int remainder = -1;
    // With CutSettings::remainderInPlace (and an open surface): the rest of the body as an
    // edit of it. It is then not among the pieces, and `remainder` is -1.
    std::optional<RemainderEdit> remainderEdit;
    // The number of primitives that were clipped (the rest were moved whole).
    int primitivesCut = 0;
    // Wall-clock seconds of each phase (for benchmarks; not part of the result's bits).
    struct Phases {
        double placement = 0.0; // cells within the radius placed in the body, their tree
        double cutting = 0.0;   // culling and clipping primitives
        double islands = 0.0;   // connections around the cuts, components, small pieces merged
        double assembly = 0.0;  // fragments' primitives, ids, connections, mass, visual meshes
    } seconds;
};

// The cut alone, without islands or surfaces (what a subdivision needs): every primitive's
// pieces, in body primitive order. A primitive that no cell within the radius cut is one
// piece, not clipped (its shape is the body's own); a cut one is its clipped pieces.
struct CutPieces {
    std::vector<int> parents;  // per piece: its body primitive (ascending)
    std::vector<bool> clipped; // per piece
    // The clipped pieces in order, in fracture-wide ids (the body's ids, new vertices
    // numbered from body.globalIdCount up, one per rest position).
    std::vector<geometry::ConvexPolyhedron> shapes;
    int primitivesCut = 0;
    double seconds = 0.0; // wall clock: placement and cutting
};

// Throws shatter::InputError naming the body for bad settings, a non-finite or zero
// placement, or a pattern with no cells or a non-positive radius (see checkPattern).
// Primitives outside every cell within the radius are copied bit for bit. When no cell within
// the radius reaches the body, the result is the body itself as the one piece (remainder 0,
// primitivesCut 0), even if it was made of several islands. Same input ⇒ same bits, with or
// without an `index` of the body's primitives (it only spares reading far primitives).
FractureResult fractureMesh(const geometry::PhysicalMesh& body, const FracturePattern& pattern, const Placement& where,
                            const CutSettings& settings, const PrimitiveIndex& index = {});

// The cutting part of fractureMesh only (same checks, same pieces, same ids).
CutPieces cutMesh(const geometry::PhysicalMesh& body, const FracturePattern& pattern, const Placement& where,
                  const CutSettings& settings);

} // namespace shatter::fracture
