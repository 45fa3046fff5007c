#include "plugin/mpm/LineCrossing.h"

#include <algorithm>

namespace shatter::mpm {

void CrackSegments::rebuild(const std::vector<Crack>& cracks, double endGap) {
    endGap_ = endGap;
    segments_.clear();
    cracks_.clear();
    for (size_t c = 0; c < cracks.size(); ++c) {
        const auto& pts = cracks[c].points;
        Range range;
        range.first = int(segments_.size());
        range.bounds = {pts.front(), pts.front()};
        double arc = 0;
        for (size_t k = 0; k + 1 < pts.size(); ++k) {
            Segment s;
            s.a = pts[k];
            s.b = pts[k + 1];
            s.normal = leftNormal(s.b - s.a).normalized();
            s.bounds = {s.a.cwiseMin(s.b), s.a.cwiseMax(s.b)};
            s.crack = int(c);
            s.arcA = arc;
            s.length = (s.b - s.a).norm();
            arc += s.length;
            range.bounds.min = range.bounds.min.cwiseMin(s.bounds.min);
            range.bounds.max = range.bounds.max.cwiseMax(s.bounds.max);
            segments_.push_back(s);
        }
        range.last = int(segments_.size());
        for (int k = range.first; k < range.last; ++k) segments_[size_t(k)].crackLength = arc;
        cracks_.push_back(range);
        bounds_ = c == 0 ? range.bounds : Box{bounds_.min.cwiseMin(range.bounds.min), bounds_.max.cwiseMax(range.bounds.max)};
    }
}

void CrackSegments::candidates(const Box& box, std::vector<int>& out) const {
    for (const Range& r : cracks_) {
        if (!r.bounds.overlaps(box)) continue;
        for (int k = r.first; k < r.last; ++k)
            if (segments_[size_t(k)].bounds.overlaps(box)) out.push_back(k);
    }
}

int CrackSegments::field(const Vec2& from, const Vec2& node, const std::vector<int>& candidates, int& crossed,
                         bool exact) const {
    const Box pair{from.cwiseMin(node), from.cwiseMax(node)};
    for (int k : candidates) {
        const Segment& s = segments_[size_t(k)];
        if (!s.bounds.overlaps(pair)) continue;
        bool above = false;
        double t = 0;
        if (!lineCrosses(from, node, s.a, s.b, above, t)) continue;
        if (!exact && endGap_ > 0) {
            const double arc = s.arcA + t * s.length;
            if (std::min(arc, s.crackLength - arc) < endGap_) continue; // within the rounding at an end
        }
        crossed = k;
        return above ? 1 : 2;
    }
    return 0;
}

} // namespace shatter::mpm
