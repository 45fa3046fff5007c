#pragma once
// Joints defined by boxes in the visual mesh (source 000 §3.1): the object name gives the
// type and the two bodies, the box's pose and extent give the joint frame.
#include <shatter/plugin/geometry/ConvexPolyhedron.h>
#include <shatter/plugin/geometry/PhysicalMesh.h>

#include <Eigen/Geometry>
#include <string>
#include <vector>

namespace shatter::geometry {

// Whether an object of that name defines a joint (it starts with "joint.").
bool isJointName(const std::string& objectName);

// Reads `joint.<fixed|hinge|ball>.<bodyA>.<bodyB>[.anything]` into the name, type and body
// fields of a JointBox. Throws InputError prefixed by `where` ("file.obj:12") for a name
// with too few parts, an unknown type, or a body joined to itself.
JointBox parseJointName(const std::string& objectName, const std::string& where);

struct OrientedBox {
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity(); // centre, proper rotation
    Eigen::Vector3d halfExtents = Eigen::Vector3d::Zero();  // decreasing
};

// The box whose surface the faces form. Its axes come from the face normals (three
// mutually orthogonal directions), its centre and half extents from the vertex
// projections; axes are sorted by decreasing half extent, and the first two point to
// the side of their largest component, the third completes a right-handed frame.
// Throws InputError prefixed by `where` when the faces are not the six sides of a box:
// normals in other directions, directions not orthogonal, vertices off the surface, or
// sides not covered exactly once. Positions are compared within 1e-6 of the box
// diagonal, but at least 1e-6 m (coordinates written with six decimals).
OrientedBox fitBox(const std::vector<Eigen::Vector3d>& points, const std::vector<std::vector<int>>& faces,
                   const std::string& where);

// The box as a convex polyhedron (for touch tests).
ConvexPolyhedron boxPolyhedron(const OrientedBox& box);

} // namespace shatter::geometry
