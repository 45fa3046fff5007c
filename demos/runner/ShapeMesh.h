#pragma once
// The surface of a plain Bullet collision shape as a polygon mesh, so balls, walls and
// hulls added by a demo appear in the frame files and pictures beside Shatter bodies.
#include <shatter/plugin/geometry/VisualMesh.h>

#include <BulletCollision/CollisionShapes/btCollisionShape.h>
#include <LinearMath/btTransform.h>

#include <string>

namespace shatter::demo {

struct ShapeMesh {
    geometry::VisualMesh mesh; // shape coordinates, polygons counter-clockwise from outside
    bool round = false;        // a tessellated curved surface (sphere, capsule, cylinder)
};

// Box, sphere, capsule and cylinder (any axis), convex hull, and compounds of these.
// Throws shatter::InputError naming `body` and the shape for anything else (a static plane
// or a triangle mesh has no closed surface to draw).
ShapeMesh tessellate(const btCollisionShape& shape, const std::string& body);

// `mesh` with every position mapped through `transform`.
geometry::VisualMesh transformed(const geometry::VisualMesh& mesh, const btTransform& transform);

} // namespace shatter::demo
