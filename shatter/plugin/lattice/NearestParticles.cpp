#include <shatter/plugin/lattice/NearestParticles.h>

#include <algorithm>
#include <cmath>

namespace shatter::lattice {

namespace {

double squared(double x) { return x * x; }

// The k smallest (squared distance, index) pairs offered so far, ascending: what sorting every
// offered pair and keeping the first k gives, without keeping the others.
class Best {
public:
    explicit Best(int k) : k_(size_t(k)) { list_.reserve(k_); }
    bool full() const { return list_.size() == k_; }
    double last() const { return list_.back().first; } // the k-th (full() only)
    void add(double distance, int index) {
        const std::pair<double, int> item(distance, index);
        if (full()) {
            if (!(item < list_.back())) return;
            list_.pop_back();
        }
        list_.insert(std::upper_bound(list_.begin(), list_.end(), item), item);
    }
    std::vector<std::pair<double, int>> take() { return std::move(list_); }

private:
    size_t k_;
    std::vector<std::pair<double, int>> list_;
};

} // namespace

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
    k = std::min(k, size());
    if (k <= 0) return {};
    if (size() <= 64) { // a small piece: looking at every point is quicker than the grid
        std::vector<std::pair<double, int>> found;
        for (int i = 0; i < size(); ++i) found.emplace_back((points_[i] - p).squaredNorm(), i);
        std::partial_sort(found.begin(), found.begin() + k, found.end());
        found.resize(size_t(k));
        return found;
    }
    const Eigen::Vector3i centre = cellOf(p);
    // Distance from p to the clamped cell's box: points outside the grid start further away.
    const Eigen::Vector3d inside = p.cwiseMax(origin_).cwiseMin(origin_ + extent_.cast<double>() * cell_);
    const double outside = (p - inside).norm();
    // What the rounding of a point's cell (cellOf) and of a cell's faces can take off a
    // distance: far below a cell, far above the rounding (extent_ is at most 65 cells).
    const double slack = 1e-6 * cell_ + 1e-12 * (origin_.cwiseAbs().maxCoeff() + p.cwiseAbs().maxCoeff());
    Best best(k);
    const int maxRing = extent_.maxCoeff();
    for (int ring = 0; ring <= maxRing; ++ring) {
        for (int x = -ring; x <= ring; ++x)
            for (int y = -ring; y <= ring; ++y) {
                // The shell only: inside its x-y outline, just the two z faces.
                const bool rim = std::abs(x) == ring || std::abs(y) == ring;
                for (int z = -ring; z <= ring; z += (rim || ring == 0) ? 1 : 2 * ring) {
                    const Eigen::Vector3i cell = centre + Eigen::Vector3i(x, y, z);
                    const int c = cellIndex(cell);
                    if (c < 0) continue;
                    // A cell whose box lies beyond the k-th nearest so far holds none of the k.
                    if (best.full() && squared(boxGap(cell, p, slack)) > best.last()) continue;
                    for (int j = cellStart_[size_t(c)]; j < cellStart_[size_t(c) + 1]; ++j)
                        best.add((points_[size_t(order_[size_t(j)])] - p).squaredNorm(), order_[size_t(j)]);
                }
            }
        // Every point not seen yet is in a cell outside this ring's block of cells.
        if (best.full() && best.last() < squared(unseenGap(centre, ring, p, outside, slack))) break;
    }
    return best.take();
}

double NearestParticles::boxGap(const Eigen::Vector3i& cell, const Eigen::Vector3d& p, double slack) const {
    const Eigen::Vector3d low = origin_ + cell.cast<double>() * cell_;
    const Eigen::Vector3d gap = (low - p).cwiseMax(p - low - Eigen::Vector3d::Constant(cell_));
    return std::max(0.0, gap.cwiseMax(0.0).norm() - slack);
}

double NearestParticles::unseenGap(const Eigen::Vector3i& centre, int ring, const Eigen::Vector3d& p, double outside,
                                   double slack) const {
    // A point in a cell beyond the block along some axis lies beyond that face of the block,
    // and (the old rule, still a bound) `ring` cells or more from the cell of p's projection
    // onto the grid box, which is `outside` away from p at a right angle.
    double gap = INFINITY;
    for (int i = 0; i < 3; ++i) {
        if (centre[i] - ring > 0) gap = std::min(gap, p[i] - (origin_[i] + (centre[i] - ring) * cell_));
        if (centre[i] + ring < extent_[i] - 1) gap = std::min(gap, origin_[i] + (centre[i] + ring + 1) * cell_ - p[i]);
    }
    const double reach = ring * cell_;
    return std::max(0.0, std::max(gap, std::sqrt(reach * reach + outside * outside)) - slack);
}

} // namespace shatter::lattice
