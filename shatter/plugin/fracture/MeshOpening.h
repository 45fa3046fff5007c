#pragma once
// Tearing in place (source 000 §3.6), for a tear that leaves the body in one piece: the
// flood fill of Tearing.h, run only from the broken connections. "We flood the graph ... by
// starting with a given primitive. However we just consider neighbors of our given primitive
// that share its global id": for every global id shared across a broken connection, the
// floods from the broken connections' primitives over unbroken connections between carriers
// of that id find the groups of carriers that still hang together; the first group (the one
// holding the lowest primitive index) keeps the id, every other group gets a new one. No
// other id, primitive, connection or face is looked at beyond flat passes over the ids.
//
// The result is the body tearMesh makes of it (its one part), with other id numbers: the same
// primitives, connections and faces, the same vertices welded (the same slots share an id),
// the same tear edges. Only the numbering differs: tearMesh renumbers every id, openMesh keeps
// them, appends the new visual ids after the old visual ones (positions copied) and the new
// inner ids at the end, and moves the inner ids up past the new visual ones (the convention
// of PhysicalMesh: visual ids first). This holds for a body whose ids are welded as tearMesh
// leaves them (the carriers of every id hang together over connections between carriers, and
// every tear edge is carried by a primitive): every mesh buildPhysicalMesh or tearMesh makes.
#include <shatter/plugin/geometry/PhysicalMesh.h>

#include <optional>
#include <utility>
#include <vector>

namespace shatter::fracture {

// What openMesh changed.
struct MeshOpening {
    // The broken connections' primitives, in the order of the connections before.
    std::vector<std::pair<int, int>> broken;
    // Per connection before: its index now, or −1 for a broken one.
    std::vector<int> connectionIndex;
    // The carriers of every id that split (those that kept it and those given a new one),
    // ascending: only their connections' shared ids and tear edges can have changed.
    std::vector<int> touched;
    // Visual faces whose corners changed, ascending.
    std::vector<int> faces;
    // New ids (as TearResult::idsSplit), and how many of them are visual: ids at or above
    // the old visual count moved up by that many.
    int idsSplit = 0;
    int visualIdsAdded = 0;
};

// Opens `body` in place along the connections flagged in `broken` (one flag per
// body.connections entry) when its unbroken connections still hold it together; otherwise
// returns nullopt and leaves it as it was (tearMesh then makes the parts). Throws
// shatter::InputError naming the body when the flags do not match the connections, or when a
// face is left with fewer than 3 corners (as tearMesh). Same input ⇒ same bits.
std::optional<MeshOpening> openMesh(geometry::PhysicalMesh& body, const std::vector<bool>& broken);

} // namespace shatter::fracture
