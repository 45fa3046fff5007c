#include <shatter/plugin/oriented/PrimitiveDeformation.h>

#include <stdexcept>

namespace shatter::oriented {

void deformedPrimitiveVertices(const OrientedSolver& solver, const std::vector<geometry::ConvexPolyhedron>& rest,
                               std::vector<std::vector<Eigen::Vector3d>>& vertices) {
    const OrientedParticles& p = solver.particles();
    if (int(rest.size()) != p.size())
        throw std::invalid_argument("deformedPrimitiveVertices: primitive and particle counts differ");
    vertices.resize(rest.size());
    const std::vector<Eigen::Matrix3d> deformations =
        solver.groups().deformations(p, p.position, p.orientation); // = solver.deformation(i), all at once
    for (int i = 0; i < p.size(); ++i) {
        const Eigen::Matrix3d& D = deformations[size_t(i)];
        const auto& restVertices = rest[i].vertices();
        vertices[i].resize(restVertices.size());
        for (size_t k = 0; k < restVertices.size(); ++k)
            vertices[i][k] = p.position[i] + D * (restVertices[k] - p.restPosition[i]);
    }
}

} // namespace shatter::oriented
