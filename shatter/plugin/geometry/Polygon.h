#pragma once
// Polygon faces of a visual mesh: clean-up of repeated vertices, planarity and convexity
// tests, and ear-clipping triangulation. A polygon is a list of indices into `points`,
// counter-clockwise seen from the side its Newell normal points to.
#include <Eigen/Core>
#include <array>
#include <vector>

namespace shatter::geometry {

// Twice the area vector of a polygon (Newell's formula taken about the first vertex, which
// keeps it accurate far from the origin). Its direction is the polygon's normal.
Eigen::Vector3d polygonAreaVector(const std::vector<Eigen::Vector3d>& points, const std::vector<int>& polygon);

// Why a face was rejected by cleanPolygon (Kept when it was not).
enum class PolygonDefect { Kept, TooFewVertices, RepeatedVertex, ZeroArea };

// Removes consecutive repeats of an index (also across the end), and with
// mergeCoincident consecutive vertices at identical coordinates. Returns the defect that
// makes the polygon unusable: fewer than 3 vertices left, an index that still repeats
// (a self-touching polygon), or a Newell normal no longer than minNormalLength.
PolygonDefect cleanPolygon(const std::vector<Eigen::Vector3d>& points, std::vector<int>& polygon,
                           double minNormalLength, bool mergeCoincident);

// Largest distance of a vertex from the plane through the vertex centroid with the
// given unit normal.
double planarityError(const std::vector<Eigen::Vector3d>& points, const std::vector<int>& polygon,
                      const Eigen::Vector3d& unitNormal);

// Whether the polygon, seen against unitNormal, turns left or goes straight at every
// vertex and winds around once (collinear vertices allowed, spikes and stars not).
bool isConvexPolygon(const std::vector<Eigen::Vector3d>& points, const std::vector<int>& polygon,
                     const Eigen::Vector3d& unitNormal);

// Ear clipping of a simple polygon in the plane perpendicular to unitNormal. Returns
// triangles of point indices with the polygon's winding; vertices on a straight edge
// stay corners of some triangle so that every vertex is used.
std::vector<std::array<int, 3>> triangulatePolygon(const std::vector<Eigen::Vector3d>& points,
                                                   const std::vector<int>& polygon, const Eigen::Vector3d& unitNormal);

} // namespace shatter::geometry
