#pragma once
// The convex hull of a set of points as a polyhedron with its faces, for a fracture shard that
// collides as its hull (FragmentHull.h). Bullet's hull computer (btConvexHullComputer, exact on
// its integer grid) gives the faces, as in Bullet's own initializePolyhedralFeatures (Bullet
// 3.24 keeps the computer's faces as they are: it merges no faces unless built with
// BT_RECONSTRUCT_FACES); buildPolyhedralFeatures (HullFeatures.h) then replaces Bullet's second
// pass over them (btConvexPolyhedron::initialize: every edge searched against every other, and
// up to 2048 containment tests for the inner box; 1.4 M instructions for a vase shard).
#include <shatter/plugin/geometry/ConvexPolyhedron.h>

#include <vector>

namespace shatter {

// The hull of `points`: its vertices are the hull computer's (the input points on its grid,
// within about 1e-4 of the points' extent of them, as in Bullet's hull; the global id of each
// is the index in `points` of the point it came from), its faces the computer's,
// counter-clockwise seen from outside, with least-squares (Newell) planes in double. Throws
// shatter::InputError when the points span no volume (fewer than 4, or all in one plane).
geometry::ConvexPolyhedron convexHullOf(const std::vector<Eigen::Vector3d>& points);

} // namespace shatter
