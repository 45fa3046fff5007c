#pragma once
// A bucket grid over the crack segments of one substep, for the field assignment's queries
// "which segments lie within a support of this particle": a particle then looks at the few
// segments listed in its bucket instead of walking every segment of every crack.
#include <shatter/plugin/mpm/LineCrossing.h>
#include <shatter/plugin/mpm/Types.h>

#include <span>
#include <vector>

namespace shatter::mpm {

class SegmentIndex {
public:
    // Buckets of side `cell` (m). Segment k is listed in every bucket that its box grown by
    // `reach` (m), plus one bucket against rounding, touches.
    void rebuild(const CrackSegments& segments, double cell, double reach);

    // The segments whose box may lie within `reach` of x (a superset of those that do), in
    // increasing index order; empty far from every crack.
    std::span<const int> near(const Vec2& x) const;

private:
    Vec2 origin_ = Vec2::Zero();
    double invCell_ = 1;
    int nx_ = 0, ny_ = 0;
    std::vector<int> start_; // bucket b lists items_[start_[b], start_[b + 1])
    std::vector<int> items_;
};

} // namespace shatter::mpm
