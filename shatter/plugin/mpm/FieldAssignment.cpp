#include <shatter/plugin/mpm/FieldAssignment.h>

#include <shatter/plugin/mpm/Grid.h>

#include <algorithm>

namespace shatter::mpm {

namespace {

// `near`: the segments that may lie within a support of x (SegmentIndex), in index order.
template <class Spline>
void fill(FieldAssignment::Entry& e, const Vec2& x, const Grid& grid, const CrackSegments& segments,
          std::span<const int> near, std::vector<int>& candidates) {
    const Stencil<Spline> st(x - grid.origin, grid.invDx);
    constexpr int W = Spline::width;
    const Box support{grid.nodePosition(st.baseX, st.baseY), grid.nodePosition(st.baseX + W - 1, st.baseY + W - 1)};
    candidates.clear();
    for (int k : near)
        if (segments.segment(k).bounds.overlaps(support)) candidates.push_back(k);
    stencilFieldsOnGrid(segments, grid, st, x, candidates, e.field.data(), e.segment.data(), e.share.data());
}

// Whether the box of half-width `reach` around x overlaps the box of one of `near`.
bool nearCrack(const Vec2& x, double reach, const CrackSegments& segments, std::span<const int> near) {
    const Box box{x - Vec2::Constant(reach), x + Vec2::Constant(reach)};
    for (int k : near)
        if (segments.segment(k).bounds.overlaps(box)) return true;
    return false;
}

} // namespace

void FieldAssignment::compute(const std::vector<Vec2>& x, const Grid& grid, const CrackSegments& segments,
                              KernelType kernel, const StripeOrder& stripes, int threads) {
    const size_t n = x.size();
    nodes = {};
    slot.assign(n, -1); // far from every crack, unless found near one below
    if (segments.empty()) {
        entries.clear();
        return;
    }
    const double reach = (kernelRadius(kernel) + 0.01) * grid.dx;
    // A node can hold two fields only where a crack segment passes within a support of it, so
    // only particles within two supports of a crack add to the nodes crack contact reads.
    const double contactReach = (2 * kernelRadius(kernel) + 0.01) * grid.dx;
    // Most particles are outside the cracks' box grown by that reach: one inline test.
    const Box band{segments.bounds().min - Vec2::Constant(contactReach),
                   segments.bounds().max + Vec2::Constant(contactReach)};
    // The particles outside the band feed field 0 only: the others' stencils (at most two
    // nodes either side of their cell) are all the crack data can reach.
    const Vec2 low = (band.min - grid.origin) * grid.invDx, high = (band.max - grid.origin) * grid.invDx;
    nodes = {floorToInt(low.x()) - 2, floorToInt(high.x()) + 2, floorToInt(low.y()) - 2, floorToInt(high.y()) + 2};
    index_.rebuild(segments, grid.dx, contactReach);
    // Only the stripes (StripeOrder.h) that reach into the band's columns hold particles that
    // can be in it: a particle's stripe does not decrease with its x. The others keep −1.
    const auto stripeAt = [&](double bx) {
        const long k = long(kernel == KernelType::Cubic ? StripeOrder::of<CubicSpline>(bx, grid.origin.x(), grid.invDx)
                                                         : StripeOrder::of<QuadraticSpline>(bx, grid.origin.x(), grid.invDx));
        return size_t(std::clamp(k, 0L, long(stripes.stripes()) - 1));
    };
    const std::uint32_t* looked = stripes.order.data() + stripes.start[stripeAt(band.min.x())];
    const size_t m = stripes.order.data() + stripes.start[stripeAt(band.max.x()) + 1] - looked;
    // Entries are numbered in the stripes' order, whatever the thread count: each block of
    // those particles (one per thread) counts its particles near a crack, and numbers them
    // after those of the earlier blocks. (The numbering changes no result: an entry is found
    // through its particle's slot.)
    const size_t blocks = size_t(std::max(1, threads));
    std::vector<std::int32_t> blockFirst(blocks + 1, 0);
#pragma omp parallel num_threads(threads)
    {
#pragma omp for schedule(static)
        for (long b = 0; b < long(blocks); ++b) {
            std::int32_t near = 0;
            for (size_t c = m * size_t(b) / blocks; c < m * size_t(b + 1) / blocks; ++c) {
                const std::uint32_t p = looked[c];
                if (!band.contains(x[p])) continue; // stays −1
                const std::span<const int> candidates = index_.near(x[p]);
                if (!nearCrack(x[p], contactReach, segments, candidates)) continue;
                if (nearCrack(x[p], reach, segments, candidates)) {
                    slot[p] = 0; // numbered below
                    ++near;
                } else {
                    slot[p] = nearContact;
                }
            }
            blockFirst[size_t(b) + 1] = near;
        }
#pragma omp single
        {
            for (size_t b = 0; b < blocks; ++b) blockFirst[b + 1] += blockFirst[b];
            // Not cleared first: fill() writes every stencil node of an entry, so the last
            // substep's entries are reused as they are (zeroing them cost ~1% of a substep).
            entries.resize(size_t(blockFirst[blocks]));
            particleOf_.resize(entries.size());
        }
#pragma omp for schedule(static)
        for (long b = 0; b < long(blocks); ++b) {
            std::int32_t next = blockFirst[size_t(b)];
            for (size_t c = m * size_t(b) / blocks; c < m * size_t(b + 1) / blocks; ++c) {
                const std::uint32_t p = looked[c];
                if (slot[p] == 0) {
                    particleOf_[size_t(next)] = p;
                    slot[p] = next++;
                }
            }
        }
        std::vector<int> candidates;
#pragma omp for schedule(dynamic, 16)
        for (long e = 0; e < long(entries.size()); ++e) {
            const Vec2& xp = x[particleOf_[size_t(e)]];
            if (kernel == KernelType::Cubic)
                fill<CubicSpline>(entries[size_t(e)], xp, grid, segments, index_.near(xp), candidates);
            else
                fill<QuadraticSpline>(entries[size_t(e)], xp, grid, segments, index_.near(xp), candidates);
        }
    }
}

} // namespace shatter::mpm
