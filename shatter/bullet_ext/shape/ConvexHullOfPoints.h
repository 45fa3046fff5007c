#pragma once
// The polyhedral features of the convex hull of a set of points, for a fracture shard that
// collides as its hull (FragmentHull.h): Bullet's own, to the bit (the hull computer's vertices
// and faces, each face's plane from its first two edges, the unique edge directions, the
// centre and inner sphere, as btPolyhedralConvexShape::initializePolyhedralFeatures and
// btConvexPolyhedron::initialize make them), except the inner box, which Bullet searches for
// with up to 2048 containment tests (half of its 2.4 M instructions for a vase shard) and which
// is found here in closed form (stretchInnerBox). Bullet's edge search (every edge against
// every other) is a window of them sorted by one coordinate here. The inner box only lets
// Bullet's separating-axis test skip axes that cannot matter, so contacts are Bullet's.
#include <BulletCollision/CollisionShapes/btConvexPolyhedron.h>

#include <Eigen/Core>

#include <vector>

namespace shatter {

// The hull of `points` (Bullet rounds them to float first). Throws shatter::InputError when
// the points span no volume (fewer than 4, or all in one plane).
btConvexPolyhedron convexHullOf(const std::vector<Eigen::Vector3d>& points);

// The inner box Bullet's initialize() searches for, in closed form (`poly` has its faces,
// centre and inner radius): a cube in the inner sphere (half side radius/√3), stretched along
// the axis of the largest extent as far as every face allows (at most half that extent), then
// widened across it as far as every face allows (at most to the inner radius). Bullet steps
// towards the same limits in 1/1024ths, so its box is at most that much smaller.
void stretchInnerBox(btConvexPolyhedron& poly);

} // namespace shatter
