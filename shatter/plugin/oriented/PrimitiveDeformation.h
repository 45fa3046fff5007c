#pragma once
// Primitive deformation for display (source 000 §3.3): each primitive's vertices follow its
// group's best-fit affine map D = A Ā⁻¹, so neighbouring primitives bend together; the
// collision primitives themselves stay rigid convex polyhedra.
#include <shatter/plugin/geometry/ConvexPolyhedron.h>
#include <shatter/plugin/oriented/OrientedSolver.h>

#include <vector>

namespace shatter::oriented {

// A body's primitive vertices as rest offsets v̄_ik − x̄_i, flat in primitive order (the
// layout geometry::VertexWelder's flat weld takes), made once: a renderer asks for the
// deformed vertices every frame, and reading 5,000 primitives' own vertex arrays each time
// (and writing as many) cost more than the arithmetic.
class PrimitiveDeformation {
public:
    // `rest` are the particles' primitives in rest coordinates (their centres are the
    // particles' rest positions), primitive i of particle i. Throws std::invalid_argument
    // when the counts differ.
    PrimitiveDeformation(const OrientedParticles& particles, const std::vector<geometry::ConvexPolyhedron>& rest);

    // vertices[j] = x_i + D_i (v̄_ik − x̄_i) for primitive i's vertex k at flat index j; at
    // rest, and under a rigid motion, the rigidly moved primitive. Throws
    // std::invalid_argument when the solver has another particle count.
    void deformedVertices(const OrientedSolver& solver, std::vector<Eigen::Vector3d>& vertices) const;

private:
    std::vector<int> first_;               // per primitive, its first flat vertex (+ the total)
    std::vector<Eigen::Vector3d> offsets_; // per flat vertex, v̄_ik − x̄_i
};

} // namespace shatter::oriented
