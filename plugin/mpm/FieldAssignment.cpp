#include "plugin/mpm/FieldAssignment.h"

#include "plugin/mpm/Grid.h"

namespace shatter::mpm {

namespace {

template <class Spline>
void fill(FieldAssignment::Entry& e, const Vec2& x, const Grid& grid, const CrackSegments& segments,
          std::vector<int>& candidates) {
    const Stencil<Spline> st(x - grid.origin, grid.invDx);
    constexpr int W = Spline::width;
    const Box support{grid.nodePosition(st.baseX, st.baseY), grid.nodePosition(st.baseX + W - 1, st.baseY + W - 1)};
    candidates.clear();
    segments.candidates(support, candidates);
    for (int i = 0; i < W; ++i)
        for (int j = 0; j < W; ++j) {
            int crossed = -1;
            const int f = candidates.empty() ? 0 : segments.field(x, grid.nodePosition(st.baseX + i, st.baseY + j),
                                                                  candidates, crossed);
            e.field[size_t(i * W + j)] = std::uint8_t(f);
            e.segment[size_t(i * W + j)] = f == 0 ? -1 : crossed;
        }
}

// Cheap first filter: the particle's support box against every crack's box.
bool nearCrack(const Vec2& x, double reach, const CrackSegments& segments) {
    return segments.anyNear(Box{x - Vec2::Constant(reach), x + Vec2::Constant(reach)});
}

} // namespace

void FieldAssignment::compute(const std::vector<Vec2>& x, const Grid& grid, const CrackSegments& segments,
                              KernelType kernel, int threads) {
    const long n = long(x.size());
    slot.assign(size_t(n), -1);
    entries.clear();
    if (segments.empty()) return;
    const double reach = (kernelRadius(kernel) + 0.01) * grid.dx;
    // A node can hold two fields only where a crack segment passes within a support of it, so
    // only particles within two supports of a crack add to the nodes crack contact reads.
    const double contactReach = (2 * kernelRadius(kernel) + 0.01) * grid.dx;
#pragma omp parallel for schedule(static) num_threads(threads)
    for (long p = 0; p < n; ++p) {
        const Vec2& xp = x[size_t(p)];
        if (!nearCrack(xp, contactReach, segments)) continue;
        slot[size_t(p)] = nearCrack(xp, reach, segments) ? 0 : nearContact;
    }
    // Serial numbering keeps the slots in particle order, whatever the thread count.
    std::int32_t next = 0;
    for (auto& s : slot)
        if (s == 0) s = next++;
    entries.resize(size_t(next));
#pragma omp parallel num_threads(threads)
    {
        std::vector<int> candidates;
#pragma omp for schedule(dynamic, 64)
        for (long p = 0; p < n; ++p) {
            const std::int32_t s = slot[size_t(p)];
            if (s < 0) continue;
            if (kernel == KernelType::Cubic)
                fill<CubicSpline>(entries[size_t(s)], x[size_t(p)], grid, segments, candidates);
            else
                fill<QuadraticSpline>(entries[size_t(s)], x[size_t(p)], grid, segments, candidates);
        }
    }
}

} // namespace shatter::mpm
