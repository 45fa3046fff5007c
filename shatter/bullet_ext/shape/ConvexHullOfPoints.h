#pragma once
// The polyhedral features of the convex hull of a set of points, for a fracture shard that
// collides as its hull (FragmentHull.h): Bullet's own, to the bit (the hull computer's vertices
// and faces, each face's plane from its first two edges, the unique edge directions, the
// centre and inner sphere, as btPolyhedralConvexShape::initializePolyhedralFeatures and
// btConvexPolyhedron::initialize make them), except the inner box, which Bullet searches for
// with up to 2,048 containment tests (24 M of the 83 M instructions Bullet spent on the 43
// shard hulls of the vase scene's break) and which is found here in closed form. Bullet's edge search (every edge against
// every other) is a window of them sorted by one coordinate here. The inner box passes
// Bullet's own float containment test (or, as Bullet's does then, is the cube Bullet starts
// from), so it only lets Bullet's separating-axis test skip axes that cannot matter, and
// contacts are Bullet's.
#include <BulletCollision/CollisionShapes/btConvexPolyhedron.h>

#include <Eigen/Core>

#include <vector>

namespace shatter {

// The hull of `points` (Bullet rounds them to float first). Throws shatter::InputError when
// the points span no volume (fewer than 4, or all in one plane).
btConvexPolyhedron convexHullOf(const std::vector<Eigen::Vector3d>& points);
// The same, into `poly`, which must be empty (std::logic_error otherwise): a hull shape's own
// features can be built in place (FragmentHull::buildFeatures) instead of copied.
void convexHullOf(const std::vector<Eigen::Vector3d>& points, btConvexPolyhedron& poly);

// convexHullOf's unique edge directions of `poly`'s faces, as btConvexPolyhedron::initialize()
// finds them, into its empty m_uniqueEdges (std::logic_error if it has some); for its test.
void findUniqueEdges(btConvexPolyhedron& poly);

} // namespace shatter
