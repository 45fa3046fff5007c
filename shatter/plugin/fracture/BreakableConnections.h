#pragma once
// Which connections of a body may break, and when they do (source 000 §3.6): "we decide
// whether a connection between two primitives is broken by using a threshold for the distance
// between these primitives", and "the artist ... can pre-define tear lines by making only a
// subset of the connections breakable". Two connected primitives share global vertex ids
// where they meet (§3.4); at rest those vertices coincide, and how far they drift apart as
// the primitives move measures how far the connection is stretched.
#include <shatter/plugin/fracture/MeshOpening.h>
#include <shatter/plugin/geometry/PhysicalMesh.h>

#include <Eigen/Geometry>
#include <span>
#include <utility>
#include <vector>

namespace shatter::fracture {

struct BreakableConnection {
    int connection = -1; // index into the body's connections
    int a = -1, b = -1;  // its primitives
    // (vertex of a, vertex of b) pairs that carry the same global id.
    std::vector<std::pair<int, int>> vertices;
};

// (global id, vertex index) of each vertex of p, sorted by id.
std::vector<std::pair<int, int>> sortedGlobalIds(const geometry::ConvexPolyhedron& p);
// (vertex of a, vertex of b) pairs with the same global id, from two sortedGlobalIds lists,
// into `out` (cleared first; its storage is reused, the callers run it once per connection).
void sharedVertices(const std::vector<std::pair<int, int>>& a, const std::vector<std::pair<int, int>>& b,
                    std::vector<std::pair<int, int>>& out);

// The breakable connections of `body`, in the order of body.connections. A connection is
// breakable when its primitives share at least one global id and come from different visual
// faces (the triangles of one split polygon are one face of the visual mesh and never part),
// and, unless `everywhere`: every visual vertex the two share lies on the body's tear lines
// (body.tearEdges), and when they share two or more, two of them form a tear edge. So the
// connections across a tear line break (edge neighbours and the diagonal neighbours meeting
// at a point of the line) and those along it do not.
std::vector<BreakableConnection> breakableConnections(const geometry::PhysicalMesh& body, bool everywhere);

// `breakable`, the list of a body before openMesh opened it in place, becomes the list of
// `body` as it is now: equal to breakableConnections(body, everywhere), found again only for
// the connections of primitives whose shared ids or tear edges may have changed
// (opening.touched); the others keep their entries, renumbered.
void updateBreakable(std::vector<BreakableConnection>& breakable, const geometry::PhysicalMesh& body,
                     const MeshOpening& opening, bool everywhere);

// Indices into `breakable` (ascending) of the connections stretched more than `distance` (m):
// two of their vertices that share a global id, with primitive p's rest vertices placed by
// poses[p] (rest coordinates → world), are farther apart than that.
std::vector<int> stretchedConnections(std::span<const BreakableConnection> breakable,
                                      const std::vector<geometry::ConvexPolyhedron>& primitives,
                                      std::span<const Eigen::Isometry3d> poses, double distance);

} // namespace shatter::fracture
