#include <shatter/plugin/lattice/NearestParticles.h>

#include <algorithm>
#include <cmath>

namespace shatter::lattice {

NearestParticles::NearestParticles(std::vector<Eigen::Vector3d> points) : points_(std::move(points)) {
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(INFINITY), hi = Eigen::Vector3d::Constant(-INFINITY);
    for (const auto& p : points_) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
    if (points_.empty()) lo = hi = Eigen::Vector3d::Zero();
    const Eigen::Vector3d size = (hi - lo).cwiseMax(1e-9);
    // About one point per cell, but never more than 64 cells along an axis: a flat or thin
    // piece would otherwise get cells far smaller than its spacing.
    const double largest = size.maxCoeff();
    cell_ = std::cbrt(size.prod() / double(std::max<size_t>(1, points_.size())));
    cell_ = std::clamp(cell_, largest / 64.0, largest / 2.0 + 1e-9);
    origin_ = lo;
    extent_ = ((hi - lo) / cell_).array().floor().cast<int>() + 1;
    // Counting sort of the points by cell: a stable order, so each cell lists increasing indices.
    cellStart_.assign(size_t(extent_.prod()) + 1, 0);
    std::vector<int> cellOfPoint(points_.size());
    for (size_t i = 0; i < points_.size(); ++i) {
        cellOfPoint[i] = cellIndex(cellOf(points_[i]));
        ++cellStart_[size_t(cellOfPoint[i]) + 1];
    }
    for (size_t c = 1; c < cellStart_.size(); ++c) cellStart_[c] += cellStart_[c - 1];
    order_.resize(points_.size());
    std::vector<int> next(cellStart_.begin(), cellStart_.end() - 1);
    for (size_t i = 0; i < points_.size(); ++i) order_[size_t(next[size_t(cellOfPoint[i])]++)] = int(i);
}

Eigen::Vector3i NearestParticles::cellOf(const Eigen::Vector3d& p) const {
    Eigen::Vector3i c = ((p - origin_) / cell_).array().floor().cast<int>();
    return c.cwiseMax(0).cwiseMin(extent_ - Eigen::Vector3i::Ones());
}

std::vector<std::pair<double, int>> NearestParticles::nearest(const Eigen::Vector3d& p, int k) const {
    std::vector<std::pair<double, int>> found;
    k = std::min(k, size());
    if (k <= 0) return found;
    if (size() <= 64) { // a small piece: looking at every point is quicker than the grid
        for (int i = 0; i < size(); ++i) found.emplace_back((points_[i] - p).squaredNorm(), i);
        std::partial_sort(found.begin(), found.begin() + k, found.end());
        found.resize(size_t(k));
        return found;
    }
    const Eigen::Vector3i centre = cellOf(p);
    // Distance from p to the clamped cell's box: points outside the grid start further away.
    const Eigen::Vector3d inside = p.cwiseMax(origin_).cwiseMin(origin_ + extent_.cast<double>() * cell_);
    const double outside = (p - inside).norm();
    const int maxRing = extent_.maxCoeff();
    for (int ring = 0; ring <= maxRing; ++ring) {
        for (int x = -ring; x <= ring; ++x)
            for (int y = -ring; y <= ring; ++y) {
                // The shell only: inside its x-y outline, just the two z faces.
                const bool rim = std::abs(x) == ring || std::abs(y) == ring;
                for (int z = -ring; z <= ring; z += (rim || ring == 0) ? 1 : 2 * ring) {
                    const int c = cellIndex(centre + Eigen::Vector3i(x, y, z));
                    if (c < 0) continue;
                    for (int j = cellStart_[size_t(c)]; j < cellStart_[size_t(c) + 1]; ++j)
                        found.emplace_back((points_[size_t(order_[size_t(j)])] - p).squaredNorm(), order_[size_t(j)]);
                }
            }
        // A point not seen yet lies `ring` cells or more from the cell of p's projection onto
        // the grid box, and that projection is `outside` away from p at a right angle.
        if (int(found.size()) >= k) {
            std::partial_sort(found.begin(), found.begin() + k, found.end());
            const double reach = ring * cell_;
            if (found[k - 1].first <= reach * reach + outside * outside) break;
        }
    }
    std::partial_sort(found.begin(), found.begin() + std::min<size_t>(k, found.size()), found.end());
    found.resize(std::min<size_t>(k, found.size()));
    return found;
}

} // namespace shatter::lattice
