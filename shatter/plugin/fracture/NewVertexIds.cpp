#include <shatter/plugin/fracture/NewVertexIds.h>

namespace shatter::fracture {

// Cells of 16 tolerances: the tolerance box around a point then lies in one cell on most
// axes (it reaches a neighbour with odds 1/8 per axis), so a look-up costs about 1.4 hash
// probes instead of the 8 that cells of two tolerances always needed; distinct new vertices
// closer than 16 tolerances (micrometres) are rare, so the chains stay short.
NewVertexIds::NewVertexIds(int firstId, double tolerance)
    : firstId_(firstId), tolerance_(tolerance), cellSize_(16.0 * tolerance),
      keys_(new std::uint64_t[16384]), heads_(16384, -1) { // a break makes thousands: no rehash on the way there
    // Room for as many ids at once (a 64-cell break of the 16k shell makes ~3.8 k): grown from
    // empty, the two lists were reallocated a dozen times each and ~115 KB copied a break.
    positions_.reserve(4096);
    next_.reserve(4096);
}

// cellOf, key and slotOf are inlined: a look-up calls them about six times, and the calls cost
// a sixth of it (callgrind).
namespace {
// (long long)std::floor(v) without the library call, for the same finite v.
long long floorOf(double v) {
    const auto i = (long long)v;
    return i - (double(i) > v ? 1 : 0);
}
} // namespace

[[gnu::always_inline]] inline Eigen::Vector3<long long> NewVertexIds::cellOf(const Eigen::Vector3d& p) const {
    return {floorOf(p.x() / cellSize_), floorOf(p.y() / cellSize_), floorOf(p.z() / cellSize_)};
}

[[gnu::always_inline]] inline std::uint64_t NewVertexIds::key(long long x, long long y, long long z) const {
    std::uint64_t h = std::uint64_t(x) * 0x9E3779B97F4A7C15ull;
    h ^= std::uint64_t(y) * 0xC2B2AE3D27D4EB4Full + (h << 6) + (h >> 2);
    h ^= std::uint64_t(z) * 0x165667B19E3779F9ull + (h << 6) + (h >> 2);
    return h;
}

[[gnu::always_inline]] inline size_t NewVertexIds::slotOf(std::uint64_t key) const {
    const size_t mask = heads_.size() - 1;
    size_t slot = size_t(key ^ (key >> 32)) & mask;
    while (heads_[slot] >= 0 && keys_[slot] != key) slot = (slot + 1) & mask;
    return slot;
}

void NewVertexIds::grow() {
    std::unique_ptr<std::uint64_t[]> keys(new std::uint64_t[2 * heads_.size()]);
    std::vector<int> heads(2 * heads_.size(), -1);
    keys.swap(keys_);
    heads.swap(heads_);
    for (size_t s = 0; s < heads.size(); ++s)
        if (heads[s] >= 0) {
            const size_t slot = slotOf(keys[s]);
            keys_[slot] = keys[s];
            heads_[slot] = heads[s];
        }
}

int NewVertexIds::idAt(const Eigen::Vector3d& p) {
    // A point within the tolerance lies in a grid cell the tolerance box around p touches:
    // at most two per axis (cells are wider than the box).
    const auto lo = cellOf(p.array() - tolerance_), hi = cellOf(p.array() + tolerance_);
    if (lo == hi) { // the box in one cell, p's own (most points): one chain, no loop nest
        const std::uint64_t k = key(lo.x(), lo.y(), lo.z());
        const size_t slot = slotOf(k);
        for (int i = heads_[slot]; i >= 0; i = next_[size_t(i)])
            if ((positions_[size_t(i)] - p).norm() <= tolerance_) return firstId_ + i;
        return add(p, k, slot);
    }
    for (long long z = lo.z(); z <= hi.z(); ++z)
        for (long long y = lo.y(); y <= hi.y(); ++y)
            for (long long x = lo.x(); x <= hi.x(); ++x)
                for (int i = heads_[slotOf(key(x, y, z))]; i >= 0; i = next_[size_t(i)])
                    if ((positions_[size_t(i)] - p).norm() <= tolerance_) return firstId_ + i;
    // p's own cell lies between lo and hi (division and floor are monotone): no division
    // needed on an axis where they agree.
    Eigen::Vector3<long long> c = lo;
    for (int k = 0; k < 3; ++k)
        if (lo[k] != hi[k]) c[k] = floorOf(p[k] / cellSize_);
    const std::uint64_t k = key(c.x(), c.y(), c.z());
    return add(p, k, slotOf(k));
}

int NewVertexIds::add(const Eigen::Vector3d& p, std::uint64_t key, size_t slot) {
    const int index = int(positions_.size());
    positions_.push_back(p);
    next_.push_back(heads_[slot]); // -1 for a cell not seen before
    if (heads_[slot] < 0) {
        keys_[slot] = key;
        ++used_;
    }
    heads_[slot] = index;
    if (2 * used_ > heads_.size()) grow(); // at most half full: probe runs stay short
    return firstId_ + index;
}

} // namespace shatter::fracture
