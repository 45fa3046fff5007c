#pragma once
// Tearing (source 000 §3.6): once connections broke, "we flood the graph which handles the
// connections between primitives by starting with a given primitive. However we just consider
// neighbors of our given primitive that share its global id." For every global id, the
// primitives carrying it that still hang together through unbroken connections between
// carriers of that id keep one id; every other such group gets a new id. So the visual mesh
// (welded by global id, §3.4) opens exactly along the broken connections and stays closed
// everywhere else. The connected components of the remaining graph become the parts.
#include <shatter/plugin/geometry/PhysicalMesh.h>

#include <vector>

namespace shatter::fracture {

struct TearResult {
    // The connected components of the body's primitives over its unbroken connections, in the
    // order of their first primitive, in the body's rest coordinates. Each has its primitives
    // (geometry bit for bit the body's, global ids renumbered: visual vertices first), its
    // unbroken connections, the body's faces over its primitives with the new ids, exact mass
    // properties (the sum of its primitives'), its tear edges and the body's name.
    std::vector<geometry::PhysicalMesh> parts;
    // Per part, per primitive: the body primitive it is.
    std::vector<std::vector<int>> parents;
    // Per part, per global id of the part: the body's global id it was split from.
    std::vector<std::vector<int>> originalIds;
    // How many more ids the parts carry than the body: the ids split along broken connections.
    int idsSplit = 0;
};

// The index of p's vertex that carries global id `id`, or −1 (a primitive has a handful of
// vertices: a scan beats sorting them).
int vertexWithId(const geometry::ConvexPolyhedron& p, int id);

// Tears `body` along the connections flagged in `broken` (one flag per body.connections
// entry). Throws shatter::InputError naming the body when the flags do not match the
// connections. With nothing broken the result is the body as one part (ids unchanged, if the
// body's primitive graph is connected). Same input ⇒ same bits.
TearResult tearMesh(const geometry::PhysicalMesh& body, const std::vector<bool>& broken);

// The index of the part with the most primitives (the first such): the part the moving
// tearMesh below leaves in the body's own vector.
int largestPart(const TearResult& torn);

// The same parts, their primitives moved out of `body`'s rather than copied (thousands of
// small allocations fewer), the largest part (largestPart) in `body`'s own vector,
// compacted: `body` is left with no primitives, to be replaced. Nothing is moved when it
// throws.
TearResult tearMesh(geometry::PhysicalMesh&& body, const std::vector<bool>& broken);

} // namespace shatter::fracture
