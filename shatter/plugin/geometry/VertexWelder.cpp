#include <shatter/plugin/geometry/VisualMesh.h>

#include <algorithm>
#include <stdexcept>
#include <string>

namespace shatter::geometry {

VertexWelder::VertexWelder(const std::vector<ConvexPolyhedron>& primitives, int visualVertexCount) {
    // Built again whenever a body's primitives change (a fracture edits a body of tens of
    // thousands): one forward pass that copies each primitive's ids and counts them, with no
    // array zeroed and then overwritten. All welders of a 16k x 64 break: 3.50 -> 3.37 M
    // instructions (it was three passes, the last one backwards).
    const int n = std::max(visualVertexCount, 0);
    const int primitiveCount = int(primitives.size());
    size_t flat = 0;
    for (const auto& p : primitives) flat += p.globalIds().size();
    vertexOffset_.reserve(primitives.size() + 1);
    flatIds_.reserve(flat);
    inverseCount_.assign(n, 0.0);
    referencePrimitive_.assign(n, -1);
    referenceVertex_.assign(n, 0);
    for (int p = 0; p < primitiveCount; ++p) {
        const auto& ids = primitives[p].globalIds();
        vertexOffset_.push_back(int(flatIds_.size()));
        flatIds_.insert(flatIds_.end(), ids.begin(), ids.end());
        for (int k = 0; k < int(ids.size()); ++k) {
            const int id = ids[k];
            if (id < 0 || id >= n) continue;
            inverseCount_[id] += 1.0;
            if (referencePrimitive_[id] < 0) { // the reference is the first vertex carrying the id
                referencePrimitive_[id] = p;
                referenceVertex_[id] = k;
            }
        }
    }
    vertexOffset_.push_back(int(flatIds_.size()));
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

std::vector<int> VertexWelder::primitivesCarrying(const std::vector<char>& ids) const {
    // One run over the flat ids; only a hit (a thousand of a 16k-primitive rest's ~130k ids)
    // looks up its primitive and skips the rest of it. Walking primitive by primitive cost
    // 1.65 M instructions of a 16k x 64 break.
    std::vector<int> found;
    const int n = int(ids.size());
    const int flatCount = int(flatIds_.size());
    for (int flat = 0; flat < flatCount; ++flat) {
        const unsigned id = unsigned(flatIds_[size_t(flat)]); // a negative id wraps past n
        if (id >= unsigned(n) || !ids[id]) continue;
        const int p = int(std::upper_bound(vertexOffset_.begin(), vertexOffset_.end(), flat) - vertexOffset_.begin()) - 1;
        found.push_back(p);
        flat = vertexOffset_[size_t(p) + 1] - 1;
    }
    return found;
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

void VertexWelder::weld(std::span<const Eigen::Vector3d> flatVertices, const Eigen::Isometry3d& transform,
                        std::vector<Eigen::Vector3d>& positions) const {
    if (flatVertices.size() != flatIds_.size()) layoutMismatch("vertex counts");
    average([&](int p, int k) -> const Eigen::Vector3d& { return flatVertices[size_t(vertexOffset_[p] + k)]; }, transform,
            positions);
}

} // namespace shatter::geometry
