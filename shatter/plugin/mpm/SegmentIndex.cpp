#include <shatter/plugin/mpm/SegmentIndex.h>

#include <shatter/plugin/mpm/BSpline.h>

#include <algorithm>

namespace shatter::mpm {

void SegmentIndex::rebuild(const CrackSegments& segments, double cell, double reach) {
    start_.assign(1, 0);
    items_.clear();
    nx_ = ny_ = 0;
    if (segments.empty()) return;
    invCell_ = 1 / cell;
    const double margin = reach + cell;
    origin_ = segments.bounds().min - Vec2::Constant(margin);
    nx_ = floorToInt((segments.bounds().max.x() + margin - origin_.x()) * invCell_) + 1;
    ny_ = floorToInt((segments.bounds().max.y() + margin - origin_.y()) * invCell_) + 1;
    // The buckets segment k covers: its box grown by reach, one bucket more on every side.
    const auto forEachBucket = [&](int k, auto&& visit) {
        const Box& b = segments.segment(k).bounds;
        const int i0 = std::max(floorToInt((b.min.x() - reach - origin_.x()) * invCell_) - 1, 0);
        const int i1 = std::min(floorToInt((b.max.x() + reach - origin_.x()) * invCell_) + 1, nx_ - 1);
        const int j0 = std::max(floorToInt((b.min.y() - reach - origin_.y()) * invCell_) - 1, 0);
        const int j1 = std::min(floorToInt((b.max.y() + reach - origin_.y()) * invCell_) + 1, ny_ - 1);
        for (int j = j0; j <= j1; ++j)
            for (int i = i0; i <= i1; ++i) visit(size_t(j) * size_t(nx_) + size_t(i));
    };
    // Counting sort into the buckets: segments enter each bucket in increasing index order.
    start_.assign(size_t(nx_) * size_t(ny_) + 1, 0);
    for (int k = 0; k < segments.size(); ++k) forEachBucket(k, [&](size_t b) { ++start_[b + 1]; });
    for (size_t b = 1; b < start_.size(); ++b) start_[b] += start_[b - 1];
    items_.resize(size_t(start_.back()));
    std::vector<int> fill(start_.begin(), start_.end() - 1);
    for (int k = 0; k < segments.size(); ++k) forEachBucket(k, [&](size_t b) { items_[size_t(fill[b]++)] = k; });
}

std::span<const int> SegmentIndex::near(const Vec2& x) const {
    const double i = (x.x() - origin_.x()) * invCell_, j = (x.y() - origin_.y()) * invCell_;
    if (!(i >= 0 && j >= 0 && i < nx_ && j < ny_)) return {}; // also for NaN
    const size_t b = size_t(j) * size_t(nx_) + size_t(i);
    return {items_.data() + start_[b], size_t(start_[b + 1] - start_[b])};
}

} // namespace shatter::mpm
