#include <shatter/plugin/fracture/NewVertexIds.h>

#include <cmath>

namespace shatter::fracture {

// Cells of 16 tolerances: the tolerance box around a point then lies in one cell on most
// axes (it reaches a neighbour with odds 1/8 per axis), so a look-up costs about 1.4 hash
// probes instead of the 8 that cells of two tolerances always needed; distinct new vertices
// closer than 16 tolerances (micrometres) are rare, so the chains stay short.
NewVertexIds::NewVertexIds(int firstId, double tolerance)
    : firstId_(firstId), tolerance_(tolerance), cellSize_(16.0 * tolerance) {
    head_.reserve(4096); // a break makes thousands: no rehash on the way there
}

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
    // A point within the tolerance lies in a grid cell the tolerance box around p touches:
    // at most two per axis (cells are wider than the box).
    const auto lo = cellOf(p.array() - tolerance_), hi = cellOf(p.array() + tolerance_);
    for (long long z = lo.z(); z <= hi.z(); ++z)
        for (long long y = lo.y(); y <= hi.y(); ++y)
            for (long long x = lo.x(); x <= hi.x(); ++x) {
                const auto it = head_.find(key(x, y, z));
                if (it == head_.end()) continue;
                for (int i = it->second; i >= 0; i = next_[size_t(i)])
                    if ((positions_[size_t(i)] - p).norm() <= tolerance_) return firstId_ + i;
            }
    const auto c = cellOf(p);
    const int index = int(positions_.size());
    positions_.push_back(p);
    auto [it, added] = head_.try_emplace(key(c.x(), c.y(), c.z()), index);
    next_.push_back(added ? -1 : it->second);
    it->second = index;
    return firstId_ + index;
}

} // namespace shatter::fracture
