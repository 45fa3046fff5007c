#pragma once
// Primitive deformation for display (source 000 §3.3): each primitive's vertices follow its
// group's best-fit affine map D = A Ā⁻¹, so neighbouring primitives bend together; the
// collision primitives themselves stay rigid convex polyhedra.
#include <shatter/plugin/geometry/ConvexPolyhedron.h>
#include <shatter/plugin/oriented/OrientedSolver.h>

#include <vector>

namespace shatter::oriented {

// vertices[i][k] = x_i + D_i (v̄_ik − x̄_i), for rest primitives in rest coordinates (their
// centres are the particles' rest positions). `vertices` is resized to the primitives'
// layout, the one geometry::VertexWelder::weld takes. At rest, and under a rigid motion,
// this is the rigidly moved primitive.
void deformedPrimitiveVertices(const OrientedSolver& solver, const std::vector<geometry::ConvexPolyhedron>& rest,
                               std::vector<std::vector<Eigen::Vector3d>>& vertices);

} // namespace shatter::oriented
