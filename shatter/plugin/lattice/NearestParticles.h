#pragma once
// Which particles are nearest to a point: a uniform grid over a fixed set of positions, so that
// spreading a contact force over its nearest particles costs O(k), not O(particles).
#include <Eigen/Core>

#include <unordered_map>
#include <utility>
#include <vector>

namespace shatter::lattice {

class NearestParticles {
public:
    // Cells about the mean spacing of the points (their bounding box volume over their
    // count, cube-rooted), so a cell holds about one point.
    explicit NearestParticles(std::vector<Eigen::Vector3d> points);

    // The k nearest points to p (indices into the constructor's list) with their squared
    // distances, nearest first; ties broken by index. Fewer when there are fewer points.
    std::vector<std::pair<double, int>> nearest(const Eigen::Vector3d& p, int k) const;
    int size() const { return int(points_.size()); }

private:
    Eigen::Vector3i cellOf(const Eigen::Vector3d& p) const;
    static long long key(const Eigen::Vector3i& c) {
        return ((long long)(c.x() & 0x1FFFFF) << 42) | ((long long)(c.y() & 0x1FFFFF) << 21) | (long long)(c.z() & 0x1FFFFF);
    }

    std::vector<Eigen::Vector3d> points_;
    Eigen::Vector3d origin_;
    double cell_ = 1.0;
    Eigen::Vector3i extent_; // cells per axis
    std::unordered_map<long long, std::vector<int>> cells_;
};

} // namespace shatter::lattice
