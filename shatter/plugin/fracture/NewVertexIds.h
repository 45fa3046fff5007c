#pragma once
// Global ids of the vertices a fracture creates (source 000 §3.6): the pattern is applied in
// the rest configuration, so vertices created at the same rest position (within the snap
// tolerance) by different cuts get one id and weld in the visual mesh.
#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <vector>

namespace shatter::fracture {

class NewVertexIds {
public:
    // New ids start at firstId (the body's globalIdCount).
    NewVertexIds(int firstId, double tolerance);

    // The id of the new vertex at p: an earlier one within the tolerance, else the next id.
    // Ids are handed out in call order, so the same cuts in the same order give the same ids.
    int idAt(const Eigen::Vector3d& p);
    int firstId() const { return firstId_; }
    int count() const { return int(positions_.size()); }
    const Eigen::Vector3d& position(int id) const { return positions_[size_t(id - firstId_)]; }

private:
    std::uint64_t key(long long x, long long y, long long z) const;
    Eigen::Vector3<long long> cellOf(const Eigen::Vector3d& p) const;
    // The hash table from grid cell key to the last id in it: open addressing with linear
    // probing (a look-up is a few loads, where std::unordered_map chased a node per probe).
    size_t slotOf(std::uint64_t key) const; // its slot, or the empty slot where it would go
    void grow();
    // A new id at p, listed first in its cell (key, at `slot`).
    int add(const Eigen::Vector3d& p, std::uint64_t key, size_t slot);

    int firstId_;
    double tolerance_;
    double cellSize_;
    // Per slot: a grid cell's key, read only where heads_ holds one, so left uninitialised:
    // zeroing 16,384 keys (128 KB) was ~65 k instructions and 32 fresh pages per break.
    std::unique_ptr<std::uint64_t[]> keys_;
    std::vector<int> heads_;          // per slot: the last id in that cell, or -1 (empty slot)
    size_t used_ = 0;                 // slots holding a cell
    std::vector<int> next_;                       // per new id: previous id in its cell, or -1
    std::vector<Eigen::Vector3d> positions_;
};

} // namespace shatter::fracture
