#include <shatter/plugin/mpm/LineCrossing.h>

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

// Inlined into the loops below (only used here), so that stencilFields computes the side of
// `from`, the same for every node, once per segment.
[[gnu::always_inline]] inline int CrackSegments::crossingField(const Segment& s, const Vec2& from, const Vec2& node,
                                                               bool exact, bool shared, double& share) const {
    bool above = false;
    share = 1;
    if (!lineCrosses(from, node, s.a, s.b, above)) return 0;
    if (!exact && endGap_ > 0) {
        // Where the particle-node pair lies along the crack, not where its line crosses it
        // (see the header).
        const double arc = s.arcA + (0.5 * (from + node) - s.a).dot(s.b - s.a) / s.length;
        const double fromEnd = std::min(arc, s.crackLength - arc);
        if (!shared) {
            if (fromEnd < endGap_) return 0; // within the rounding at an end
        } else {
            const double ramp = std::clamp((fromEnd - endGap_) / endGap_ + 0.5, 0.0, 1.0);
            share = ramp * ramp; // the end linear in the ramp, not the cut weight (see the header)
            if (share == 0) return 0;
        }
    }
    return above ? 1 : 2;
}

int CrackSegments::field(const Vec2& from, const Vec2& node, const std::vector<int>& candidates, int& crossed,
                         bool exact) const {
    const Box pair{from.cwiseMin(node), from.cwiseMax(node)};
    for (int k : candidates) {
        const Segment& s = segments_[size_t(k)];
        if (!s.bounds.overlaps(pair)) continue;
        double share;
        if (const int f = crossingField(s, from, node, exact, false, share)) {
            crossed = k;
            return f;
        }
    }
    return 0;
}

void CrackSegments::stencilFields(const Vec2& from, const double* xs, const double* ys, int W,
                                  const std::vector<int>& candidates, std::uint8_t* fields,
                                  std::int32_t* crossed, double* share) const {
    for (int k = 0; k < W * W; ++k) {
        fields[k] = 0;
        crossed[k] = -1;
        if (share) share[k] = 0;
    }
    for (int c : candidates) {
        const Segment& s = segments_[size_t(c)];
        // Box(from, node) overlaps the segment's box: an interval test on each axis.
        bool xOverlaps[4], yOverlaps[4];
        for (int k = 0; k < W; ++k) {
            xOverlaps[k] = s.bounds.min.x() <= std::max(from.x(), xs[k]) && std::min(from.x(), xs[k]) <= s.bounds.max.x();
            yOverlaps[k] = s.bounds.min.y() <= std::max(from.y(), ys[k]) && std::min(from.y(), ys[k]) <= s.bounds.max.y();
        }
        for (int i = 0; i < W; ++i) {
            if (!xOverlaps[i]) continue;
            for (int j = 0; j < W; ++j) {
                const int k = i * W + j;
                if (!yOverlaps[j] || fields[k] != 0) continue; // an earlier segment decided
                double pairShare;
                if (const int f = crossingField(s, from, Vec2(xs[i], ys[j]), false, share != nullptr, pairShare)) {
                    fields[k] = std::uint8_t(f);
                    crossed[k] = c;
                    if (share) share[k] = pairShare;
                }
            }
        }
    }
}

} // namespace shatter::mpm
