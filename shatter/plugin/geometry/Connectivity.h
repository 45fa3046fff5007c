#pragma once
// Which primitives touch or overlap at rest (source 000 §3.1): an AABB-tree broadphase and
// a libccd GJK narrowphase on the primitives grown by half the tolerance each, so that
// two convex solids count as touching when their distance is at most the tolerance.
#include <shatter/plugin/geometry/ConvexPolyhedron.h>

#include <utility>
#include <vector>

namespace shatter::geometry {

// Whether the id lists a and b have an id in common (pieces that share a vertex id touch;
// fracture's island test). A shared id is found soonest when it is early in `a`.
bool shareAnId(const std::vector<int>& a, const std::vector<int>& b);

// Whether a and b are at most `tolerance` apart (0 for overlap or contact). GJK runs on
// a and b each grown by a sphere of radius tolerance/2.
bool withinTolerance(const ConvexPolyhedron& a, const ConvexPolyhedron& b, double tolerance);

// All pairs (a < b) of primitives at most `tolerance` apart, sorted.
std::vector<std::pair<int, int>> touchingPairs(const std::vector<ConvexPolyhedron>& primitives, double tolerance);

// Primitives at most `tolerance` from `probe`, ascending.
std::vector<int> primitivesTouching(const std::vector<ConvexPolyhedron>& primitives, const ConvexPolyhedron& probe,
                                    double tolerance);

// Number of connected components of a graph over nodes 0..nodeCount-1.
int countComponents(int nodeCount, const std::vector<std::pair<int, int>>& edges);

} // namespace shatter::geometry
