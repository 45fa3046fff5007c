#include <shatter/plugin/oriented/PrimitiveDeformation.h>

#include <string>
#include <stdexcept>

namespace shatter::oriented {

PrimitiveDeformation::PrimitiveDeformation(const OrientedParticles& particles,
                                           const std::vector<geometry::ConvexPolyhedron>& rest) {
    if (int(rest.size()) != particles.size())
        throw std::invalid_argument("PrimitiveDeformation: " + std::to_string(rest.size()) + " primitives for " +
                                    std::to_string(particles.size()) + " particles");
    first_.reserve(rest.size() + 1);
    for (size_t i = 0; i < rest.size(); ++i) {
        first_.push_back(int(offsets_.size()));
        for (const Eigen::Vector3d& v : rest[i].vertices()) offsets_.push_back(v - particles.restPosition[i]);
    }
    first_.push_back(int(offsets_.size()));
}

void PrimitiveDeformation::deformedVertices(const OrientedSolver& solver, std::vector<Eigen::Vector3d>& vertices) const {
    const OrientedParticles& p = solver.particles();
    if (size_t(p.size()) + 1 != first_.size())
        throw std::invalid_argument("PrimitiveDeformation: made for " + std::to_string(first_.size() - 1) +
                                    " primitives, the solver has " + std::to_string(p.size()) + " particles");
    vertices.resize(offsets_.size());
    const std::vector<Eigen::Matrix3d> deformations =
        solver.groups().deformations(p, p.position, p.orientation, // = solver.deformation(i), all at once
                                     solver.settings().simdPath);
    for (int i = 0; i < p.size(); ++i) {
        const Eigen::Matrix3d& D = deformations[size_t(i)];
        const Eigen::Vector3d& x = p.position[i];
        for (int j = first_[size_t(i)]; j < first_[size_t(i) + 1]; ++j) vertices[size_t(j)] = x + D * offsets_[size_t(j)];
    }
}

} // namespace shatter::oriented
