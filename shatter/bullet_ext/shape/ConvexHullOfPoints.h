#pragma once
// The convex hull of a set of points as a polyhedron with its faces, for a fracture shard that
// collides as its hull (FragmentHull.h). Bullet's hull computer (exact on its integer grid)
// gives the topology; the faces are then merged as Bullet's initializePolyhedralFeatures merges
// them, so the hull has the faces Bullet's own would have, without Bullet's second pass over
// them (btConvexPolyhedron::initialize: a search of every edge against every other and up to
// 2048 containment tests for the inner box, 2.4 M instructions for a shard of a few hundred
// points).
#include <shatter/plugin/geometry/ConvexPolyhedron.h>

#include <vector>

namespace shatter {

// Normals closer than this (their dot product above it) make one face: Bullet's weld threshold
// in initializePolyhedralFeatures. A crack face split by rounding into nearly coplanar pieces
// is one face again, as in Bullet's hull.
constexpr double kFaceWeldCosine = 0.999;

// The hull of `points`: its vertices are the input points it passes through (bit for bit; the
// global id of each is its index in `points`), its faces counter-clockwise seen from outside,
// each the convex hull (in its plane) of the computer's faces whose normals are within
// kFaceWeldCosine of one another and connected through shared edges. Faces so merged are
// planar within that tolerance: their plane is the least-squares (Newell) one. Throws
// shatter::InputError when the points span no volume (fewer than 4, or all in one plane).
geometry::ConvexPolyhedron convexHullOf(const std::vector<Eigen::Vector3d>& points);

} // namespace shatter
