#pragma once
// The rest of a fractured body as an edit of the body itself (source 000 §3.6): a body of tens
// of thousands of primitives that loses a few hundred near the impact keeps everything else
// where it is, so the Bullet side can drop and add primitives instead of building a new body.
#include <shatter/plugin/geometry/PhysicalMesh.h>

#include <utility>
#include <vector>

namespace shatter::fracture {

// What turns the body into the rest of it. Primitive indices are the body's; ids are the
// body's global ids (new vertices numbered from its globalIdCount up), renumbered by idSwaps
// so that the visual vertices still come first (PhysicalMesh's rule).
struct RemainderEdit {
    std::vector<int> removed;                      // body primitives it loses (cut or cut free), ascending
    std::vector<geometry::ConvexPolyhedron> added; // cut pieces it gains (final ids), counted after the kept ones
    // Id pairs exchanged in the kept primitives: inner ids that become visual vertices (they
    // show on a crack face) trade places with inner ids among the first ones after the old
    // visual vertices. Both sides of every pair are swapped.
    std::vector<std::pair<int, int>> idSwaps;
    std::vector<int> droppedFaces;        // visual faces (body indices) it no longer shows, ascending
    std::vector<std::vector<int>> faces;  // visual faces it gains (final ids)
    std::vector<bool> crack;              // per gained face: a crack face
    std::vector<int> lostSourceFace;      // kept primitives whose source face is no longer shown whole
    std::vector<std::pair<int, int>> connections; // gained connections (a < b): kept ones counted in order, then added
    // Indices into the body's connections, ascending: every connection with an end in
    // `removed` is listed (others may be). applyRemainderEdit keeps the others in runs,
    // renumbered only where an end moved (fractureMesh fills it; an edit made by hand must list
    // them all). It checks first: an unlisted connection with a removed end, or indices not
    // ascending or out of range, throw shatter::InputError naming the body and the removed
    // primitive, and leave the body as it was (unless the caller says TouchedList::FromEveryConnection).
    std::vector<int> touchedConnections;
    // Positions of the new visual vertices: ids visualCount .. visualCount + size - 1.
    std::vector<Eigen::Vector3d> newVisualPositions;
    int globalIdCount = 0;
    // By subtraction: the body's mass properties less those of every other fragment, so the
    // fragments and the rest add up to the body exactly (no sum over the kept primitives).
    geometry::MassProperties mass;
};

// Applies the edit: the kept primitives keep their geometry bit for bit and, but for idSwaps,
// their ids; their places and the added pieces' are those of geometry::fillHoles(primitive
// count, removed, added.size()) (the pieces take the removed primitives' places, the last
// survivors fill the holes left), so only O(removed + added) primitives move, and a group
// shape edited with the same call (GroupShape::fillPrimitives) keeps the same order. The
// edit's own connection indices (kept primitives in order, then the added ones) are mapped
// to those places. Cost O(removed + added) primitives plus O(primitives + ids + faces)
// integers, copying only the primitives whose ids change.
void applyRemainderEdit(geometry::PhysicalMesh& body, const RemainderEdit& edit);

// Storage applyRemainderEdit works in, which a body keeps from one break to the next, so that a
// break neither allocates nor frees arrays the size of the body (the 16k shell: ~0.5 MB of
// connections, ~16k-entry primitive and face maps, a table over a break's new ids). Between calls the
// content is unspecified but for swapTable, which is -1 everywhere (an edit resets the
// entries it wrote, not the whole table); `connections` holds the body's old list.
struct RemainderScratch {
    std::vector<std::pair<int, int>> connections; // the new connection list is built here
    std::vector<int> to;                          // each old primitive's place (-1: removed)
    std::vector<int> faceTo;                      // each old face's place (-1: dropped)
    std::vector<int> finalTo;                     // the edit's own primitive numbering's places
    std::vector<int> swapTable;                   // the other id of a swapped one (from the lowest), or -1
    // Room for a body of `primitives`, `connections`, `faces` and `ids` and some growth.
    void reserveFor(size_t primitives, size_t connections, size_t faces, size_t ids);
};

// How far applyRemainderEdit checks touchedConnections. FromEveryConnection: the caller
// passes fractureMesh's edit of this very body, unchanged, whose list was found by reading
// every connection (its islands look at each one): the connections kept in place are then not
// looked up at both ends (keptConnections 3.82 -> 2.56 M instructions in five 16k-primitive
// breaks); one it renumbers is still checked. A call's argument, not a field of the edit, so
// that a copy of an edit changed by hand is never trusted by accident.
enum class TouchedList { Checked, FromEveryConnection };

// Same, moving the added pieces into the body instead of copying them: `pieces` are the edit's
// `added`, taken out of it by the caller (`applyRemainderEdit(mesh, edit, std::move(edit.added),
// carriers)`, so the call says what is moved; `pieces` is left empty). In a 16k-primitive break
// this saves copying and later freeing ~320 polyhedra (~1 M instructions of the event).
// `swapCarriers` are the ascending indices of the body's primitives that carry an id of
// edit.idSwaps (more may be listed, none may be missing; geometry::VertexWelder::
// primitivesCarrying): only their ids are read, where the other overload reads every kept
// primitive's (one scattered block each). `scratch`, when given: the storage the edit works
// in (RemainderScratch). Same result.
void applyRemainderEdit(geometry::PhysicalMesh& body, const RemainderEdit& edit,
                        std::vector<geometry::ConvexPolyhedron>&& pieces, const std::vector<int>& swapCarriers,
                        RemainderScratch* scratch = nullptr, TouchedList touched = TouchedList::Checked);
// The ids edit.idSwaps exchanges (both sides of every pair).
std::vector<int> swappedIds(const RemainderEdit& edit);

// The face part of the edit alone (drop, gain, crack flags), for a copy of the body's visual
// faces that must follow it (a body's world-space visual mesh). The faces' places are
// geometry::fillHoles(face count, droppedFaces, faces.size())'s, as applyRemainderEdit's.
void applyFaceEdit(geometry::VisualMesh& visual, const RemainderEdit& edit);

// `whole` less `part`: the mass properties of what is left when `part` is taken out of `whole`
// (the inverse of MassProperties::operator+=).
geometry::MassProperties withoutPart(const geometry::MassProperties& whole, const geometry::MassProperties& part);

} // namespace shatter::fracture
