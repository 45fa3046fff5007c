#include <shatter/plugin/fracture/NewVertexIds.h>

#include <cmath>

namespace shatter::fracture {

NewVertexIds::NewVertexIds(int firstId, double tolerance)
    : firstId_(firstId), tolerance_(tolerance), cellSize_(2.0 * tolerance) {}

Eigen::Vector3<long long> NewVertexIds::cellOf(const Eigen::Vector3d& p) const {
    return {(long long)std::floor(p.x() / cellSize_), (long long)std::floor(p.y() / cellSize_),
            (long long)std::floor(p.z() / cellSize_)};
}

std::uint64_t NewVertexIds::key(long long x, long long y, long long z) const {
    std::uint64_t h = std::uint64_t(x) * 0x9E3779B97F4A7C15ull;
    h ^= std::uint64_t(y) * 0xC2B2AE3D27D4EB4Full + (h << 6) + (h >> 2);
    h ^= std::uint64_t(z) * 0x165667B19E3779F9ull + (h << 6) + (h >> 2);
    return h;
}

int NewVertexIds::idAt(const Eigen::Vector3d& p) {
    // A point within the tolerance lies in this grid cell or a neighbouring one (cells are
    // two tolerances wide).
    const auto c = cellOf(p);
    for (long long dz = -1; dz <= 1; ++dz)
        for (long long dy = -1; dy <= 1; ++dy)
            for (long long dx = -1; dx <= 1; ++dx) {
                const auto it = head_.find(key(c.x() + dx, c.y() + dy, c.z() + dz));
                if (it == head_.end()) continue;
                for (int i = it->second; i >= 0; i = next_[size_t(i)])
                    if ((positions_[size_t(i)] - p).norm() <= tolerance_) return firstId_ + i;
            }
    const int index = int(positions_.size());
    positions_.push_back(p);
    auto [it, added] = head_.try_emplace(key(c.x(), c.y(), c.z()), index);
    next_.push_back(added ? -1 : it->second);
    it->second = index;
    return firstId_ + index;
}

} // namespace shatter::fracture
