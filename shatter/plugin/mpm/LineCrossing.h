#pragma once
// The line-crossing test of CRAMP (Nairn 2003; §3.1.1 of 001): a particle's contribution to
// a node goes to another velocity field when the straight line from the particle to the
// node crosses a crack. The test is the costliest part of crack handling, so it is filtered
// first by bounding boxes: per crack, then per segment against the particle's support box.
//
// Crack ends and the grid. Velocity fields are all-or-nothing: once a particle feeds a
// second field at a node, that field must be in equilibrium on its own, so in a static
// solution a node is either split or not, whatever share of its particles crossed. A crack
// end therefore resolves only to the grid: with the plain test the discrete crack runs on to
// the next node past the end (a tip 1/8 cell past a grid line acted as if a whole cell
// longer: K_I +10.5%). `endGap` rounds instead of truncating: a line whose particle-node
// midpoint lies (projected on the crossed segment) within endGap (half a cell) of one of the
// crack's ends does not count. The share of a node's particles that feed its second field
// then follows the tip's place in the cell, so the discrete crack ends near the true end.
//
// The rounding looks at the midpoint of the pair, not at where the line crosses the crack
// (issue 20). The crossing point depends on how far the particle and the node are from the
// crack line, so with the line off the grid lines (a third of a cell above one, nodes 1/3
// below and 2/3 above it) the lines from the particles above and from those below were cut
// off at different places: the two faces ended at different nodes, the faces slid near the
// tip and a symmetric crack in pure tension showed |K_II|/K_I = 0.037 (cubic kernel, 2
// particles per cell per axis, a/dx = 16), still creeping after five wave transits as the
// near-tip field relaxed. The midpoint's place along the crack does not change when the
// particle and the node swap sides: K_II = 0. (The node's own place also gave K_II = 0, but
// rounds each node whole: K_I −2.7% and −3.9% with the tips 1/4 and 1/2 cell past a grid
// line at a/dx = 16, against −1.9% and +0.4% with the midpoint.)
//
// Shares: the tip inside a cell (issue 20). Rounding all or nothing still resolves the end
// only in steps: with 2 particles per cell the pairs at the node nearest the tip switch in
// four groups per cell, and the one that matters (the particle just behind that node) moves
// the effective end by about 0.8 cell at once. At a/dx = 16 (1 cell ≈ 5.6% of K_I) the tips
// 1/4 cell past a grid line acted as if on the node: K_I −2.0% to −2.35%, and no shift of
// the rounding passes all four tip offsets (a shift only moves which offset falls on the
// step). So a pair is shared instead: a node stands for its cell, and the share of the pair's
// contribution that goes to the crossed field is the part of the node's cell whose points,
// paired with the particle, the rounding counts. Over the node's cell the midpoint spreads
// over ±endGap/2 (endGap is half a cell), so that part, r, rises linearly from 0 with the
// midpoint endGap/2 from the end to 1 at 3·endGap/2. The share is r², not r: the rest goes
// to field 0, by the same split in the particle-to-grid and the grid-to-particle transfers
// (mass and momentum are kept), and a pair shared with r acts as more than r of a cut (the
// effective end is concave in the share: a weakened link near the tip opens more than its
// weight says), so r biased every tip long. Measured (a/dx = 16, cubic, 2 ppc, crack lines 0 to 1/2 x
// tips 0 to 3/4 cell; K_I vs the FE reference): share r: −1.1% to +1.9%; r²: −1.6% to +0.6%;
// r^2.5: −2.2% (FAIL, tips 1/4) to +0.4%; all or nothing (r rounded): −2.35% (FAIL) to
// +1.3%. |K_II|/K_I ≤ 0.35% with each. On the 45° inclined crack (quadratic, 3 ppc, a/dx = 8)
// the bias of r was larger, K_II +6.4/+6.7% (bound 5%); with r² +4.9/+4.6%. That row depends
// on where the tips fall in their cells with any rule: shifting the crack along itself by
// 1/4, 1/2, 3/4 cell, K_II (start/end tip) is +5.8/+7.0, +5.7/+6.1, +4.6/+3.7% with r² and
// +5.5/+5.5, +6.1/+4.9, +2.8/+2.0% rounded (notes/mpmshare2.md). The mode II of an
// inclined crack is too high by itself (faces slide too much, issue 20); the shares add to it.
#include <shatter/plugin/mpm/Crack.h>
#include <shatter/plugin/mpm/Types.h>

#include <cstdint>
#include <vector>

namespace shatter::mpm {

// All crack segments of one substep, frozen while the transfers run.
class CrackSegments {
public:
    struct Segment {
        Vec2 a, b;       // endpoints, in the crack's point order
        Vec2 normal;     // unit left normal: points to the "above" side
        Box bounds;
        int crack = 0;
        double arcA = 0;        // arc length of the crack from its first point to a
        double length = 0;      // |b − a|
        double crackLength = 0; // of the whole polyline
    };

    // `endGap` (m): see above; 0 gives Nairn's plain test.
    void rebuild(const std::vector<Crack>& cracks, double endGap = 0);
    bool empty() const { return segments_.empty(); }
    int size() const { return int(segments_.size()); }
    const Segment& segment(int k) const { return segments_[size_t(k)]; }

    // Appends to `out` the segments whose bounding box overlaps `box` (crack boxes first).
    void candidates(const Box& box, std::vector<int>& out) const;
    // The box of all segments (call only when not empty).
    const Box& bounds() const { return bounds_; }

    // The field a particle at `from` feeds at `node`: 0 when the line between them crosses
    // none of `candidates`, 1 when it crosses one and `from` is above it, 2 when below.
    // The first crossed segment (in crack, then point order) decides; `crossed` gets it.
    // Points exactly on a crack line count as below it, so the rule is a partition.
    // `exact`: ignore endGap (the J-integral's side test wants the true geometry).
    int field(const Vec2& from, const Vec2& node, const std::vector<int>& candidates, int& crossed,
              bool exact = false) const;
    // field() of one particle at all nodes of its W x W stencil (W ≤ 4), node (i, j) at
    // (xs[i], ys[j]): fields[i·W + j], and crossed[i·W + j] (−1 where the field is 0). The
    // same result as field() node by node, with the bounding-box filter split over the axes:
    // 2W interval tests per segment instead of W² box tests.
    // `share` (may be null): per node, the share of the particle's contribution that goes to
    // fields[k] (the rest to field 0); without it the rounding above decides all or nothing.
    void stencilFields(const Vec2& from, const double* xs, const double* ys, int W, const std::vector<int>& candidates,
                       std::uint8_t* fields, std::int32_t* crossed, double* share = nullptr) const;

private:
    // 1 or 2 (the side of `from`) when the line from→node crosses s, away from the crack's
    // ends unless `exact`; 0 otherwise. `share` gets the pair's share (1 when exact).
    int crossingField(const Segment& s, const Vec2& from, const Vec2& node, bool exact, bool shared,
                      double& share) const;

    std::vector<Segment> segments_;
    struct Range {
        Box bounds;
        int first = 0, last = 0; // segment index range [first, last)
    };
    std::vector<Range> cracks_;
    Box bounds_;
    double endGap_ = 0;
};

// True when the line p→q crosses segment a→b (touching counts), and which side p is on;
// `t` gets where along a→b (0..1) the crossing is.
inline bool lineCrosses(const Vec2& p, const Vec2& q, const Vec2& a, const Vec2& b, bool& pAbove, double& t) {
    const double sp = orient(a, b, p), sq = orient(a, b, q);
    const bool abovePq[2] = {sp > 0, sq > 0};
    if (abovePq[0] == abovePq[1]) return false;
    const double sa = orient(p, q, a), sb = orient(p, q, b);
    if ((sa > 0 && sb > 0) || (sa < 0 && sb < 0)) return false;
    pAbove = abovePq[0];
    t = sa == sb ? 0.5 : sa / (sa - sb);
    return true;
}
inline bool lineCrosses(const Vec2& p, const Vec2& q, const Vec2& a, const Vec2& b, bool& pAbove) {
    double t;
    return lineCrosses(p, q, a, b, pAbove, t);
}

} // namespace shatter::mpm
