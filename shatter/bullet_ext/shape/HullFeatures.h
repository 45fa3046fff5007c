#pragma once
// Bullet's polyhedral features (btConvexPolyhedron: vertices, faces with planes, unique edge
// directions, the inner sphere and box) built from a polyhedron whose faces are known, instead
// of Bullet's initializePolyhedralFeatures (a hull computed again from the points, then up to
// 2048 containment tests for the inner box). Group shape children are made this way.
#include <shatter/plugin/geometry/ConvexPolyhedron.h>

#include <BulletCollision/CollisionShapes/btConvexPolyhedron.h>

namespace shatter {

// All of `p`'s features into `poly` (empty): its vertices, its faces with their planes
// (Bullet's plane is n·x + w = 0, outward n), unique edges and internal objects.
void buildPolyhedralFeatures(const geometry::ConvexPolyhedron& p, btConvexPolyhedron& poly);

// Edge directions of the polyhedron, each once up to sign (Bullet's tolerance, 1e-6 per
// component): the edge-edge axes of Bullet's separating-axis test. Appended to poly.
void addUniqueEdges(const geometry::ConvexPolyhedron& p, btConvexPolyhedron& poly);

// The radius of the inner sphere about the interior point `c` (the distance to the nearest face).
btScalar innerRadius(const geometry::ConvexPolyhedron& p, const Eigen::Vector3d& c);

// The "internal objects" Bullet's separating-axis test uses to skip axes: a sphere and a box
// about the centroid that lie inside the polyhedron, and its bounding box (mC, mE).
void setInternalObjects(const geometry::ConvexPolyhedron& p, btConvexPolyhedron& poly);

} // namespace shatter
