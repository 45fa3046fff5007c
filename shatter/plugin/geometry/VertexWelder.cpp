#include <shatter/plugin/geometry/VisualMesh.h>

#include <algorithm>
#include <stdexcept>
#include <string>

namespace shatter::geometry {

VertexWelder::VertexWelder(const std::vector<ConvexPolyhedron>& primitives, int visualVertexCount) {
    // Built again whenever a body's primitives change (a fracture edits a body of tens of
    // thousands): flat passes with no per-vertex push_back.
    const int n = std::max(visualVertexCount, 0);
    const int primitiveCount = int(primitives.size());
    vertexOffset_.resize(primitives.size() + 1);
    int flat = 0;
    for (int p = 0; p < primitiveCount; ++p) {
        vertexOffset_[p] = flat;
        flat += int(primitives[p].globalIds().size());
    }
    vertexOffset_[primitiveCount] = flat;
    flatIds_.resize(size_t(flat));
    for (int p = 0; p < primitiveCount; ++p)
        std::copy(primitives[p].globalIds().begin(), primitives[p].globalIds().end(), flatIds_.begin() + vertexOffset_[p]);
    inverseCount_.assign(n, 0.0);
    referencePrimitive_.assign(n, -1);
    referenceVertex_.assign(n, 0);
    // Backwards, so the reference left in place is the first vertex carrying the id.
    for (int p = primitiveCount - 1; p >= 0; --p)
        for (int flatIndex = vertexOffset_[p + 1] - 1; flatIndex >= vertexOffset_[p]; --flatIndex) {
            const int id = flatIds_[flatIndex];
            if (id < 0 || id >= n) continue;
            inverseCount_[id] += 1.0;
            referencePrimitive_[id] = p;
            referenceVertex_[id] = flatIndex - vertexOffset_[p];
        }
    for (double& c : inverseCount_) c = c > 0.0 ? 1.0 / c : 0.0;
}

template <class VertexAt>
void VertexWelder::average(const VertexAt& vertex, const Eigen::Isometry3d& transform,
                           std::vector<Eigen::Vector3d>& positions) const {
    const int n = int(inverseCount_.size());
    positions.resize(n);
    for (int id = 0; id < n; ++id)
        if (referencePrimitive_[id] >= 0) positions[id].setZero();
    // Offsets from the reference vertex: exactly zero for coincident vertices, and small
    // numbers (no cancellation) for a mesh far from the origin.
    const int primitiveCount = int(vertexOffset_.size()) - 1;
    for (int p = 0; p < primitiveCount; ++p)
        for (int flat = vertexOffset_[p]; flat < vertexOffset_[p + 1]; ++flat) {
            const int id = flatIds_[flat];
            if (id < 0 || id >= n) continue;
            const Eigen::Vector3d& ref = vertex(referencePrimitive_[id], referenceVertex_[id]);
            positions[id] += (vertex(p, flat - vertexOffset_[p]) - ref) * inverseCount_[id];
        }
    for (int id = 0; id < n; ++id)
        if (referencePrimitive_[id] >= 0)
            positions[id] = transform * (vertex(referencePrimitive_[id], referenceVertex_[id]) + positions[id]);
}

namespace {

[[noreturn]] void layoutMismatch(const std::string& what) {
    throw std::invalid_argument("VertexWelder::weld: " + what + " differ from those the welder was built for");
}

} // namespace

void VertexWelder::weld(const std::vector<ConvexPolyhedron>& primitives, const Eigen::Isometry3d& transform,
                        std::vector<Eigen::Vector3d>& positions) const {
    if (primitives.size() + 1 != vertexOffset_.size()) layoutMismatch("primitive count");
    for (size_t p = 0; p < primitives.size(); ++p)
        if (int(primitives[p].vertices().size()) != vertexOffset_[p + 1] - vertexOffset_[p])
            layoutMismatch("vertex counts");
    average([&](int p, int k) -> const Eigen::Vector3d& { return primitives[p].vertices()[k]; }, transform, positions);
}

void VertexWelder::weld(const std::vector<std::vector<Eigen::Vector3d>>& primitiveVertices,
                        const Eigen::Isometry3d& transform, std::vector<Eigen::Vector3d>& positions) const {
    if (primitiveVertices.size() + 1 != vertexOffset_.size()) layoutMismatch("primitive count");
    for (size_t p = 0; p < primitiveVertices.size(); ++p)
        if (int(primitiveVertices[p].size()) != vertexOffset_[p + 1] - vertexOffset_[p]) layoutMismatch("vertex counts");
    average([&](int p, int k) -> const Eigen::Vector3d& { return primitiveVertices[p][k]; }, transform, positions);
}

} // namespace shatter::geometry
