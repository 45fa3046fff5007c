#pragma once
// Which velocity field each particle feeds at each node of its stencil, for the particles
// whose support reaches a crack (all others feed field 0 everywhere). Computed once per
// substep and shared by the particle-to-grid and grid-to-particle transfers, so that both
// see the same fields (Nairn 2003).
#include <shatter/plugin/mpm/BSpline.h>
#include <shatter/plugin/mpm/Grid.h>
#include <shatter/plugin/mpm/LineCrossing.h>
#include <shatter/plugin/mpm/SegmentIndex.h>
#include <shatter/plugin/mpm/StripeOrder.h>
#include <shatter/plugin/mpm/Types.h>

#include <array>
#include <cstdint>
#include <vector>

namespace shatter::mpm {

// The fields a particle at `from` feeds at the nodes of its stencil `st` on `grid`, and the
// segments crossed (CrackSegments::stencilFields at the grid's node coordinates).
template <class Spline>
void stencilFieldsOnGrid(const CrackSegments& segments, const Grid& grid, const Stencil<Spline>& st,
                         const Vec2& from, const std::vector<int>& candidates, std::uint8_t* fields,
                         std::int32_t* crossed, double* share = nullptr) {
    constexpr int W = Spline::width;
    double xs[W], ys[W]; // as Grid::nodePosition gives them
    for (int k = 0; k < W; ++k) {
        xs[k] = grid.nodePosition(st.baseX + k, st.baseY).x();
        ys[k] = grid.nodePosition(st.baseX, st.baseY + k).y();
    }
    segments.stencilFields(from, xs, ys, W, candidates, fields, crossed, share);
}

struct FieldAssignment {
    static constexpr int maxStencil = 16; // 4 x 4 nodes of the cubic spline

    struct Entry {
        std::array<std::uint8_t, maxStencil> field{};  // 0, 1 or 2, per stencil node (i·W + j)
        std::array<std::int32_t, maxStencil> segment{}; // crossed segment, or −1
        std::array<double, maxStencil> share{};         // of the contribution to field[k] (rest: field 0)
    };
    // Per particle: index into entries; −1 when far from cracks; nearContact when the
    // particle feeds field 0 only but reaches nodes where crack contact may act.
    static constexpr std::int32_t nearContact = -2;
    std::vector<std::int32_t> slot;
    std::vector<Entry> entries;
    // The grid nodes the particles near a crack reach: the only ones they give crack data
    // (Grid::clearCrackData).
    Grid::NodeRange nodes;

    // Recomputes the assignment for particle positions `x` on `grid`, sorted into `stripes`
    // on it (only the stripes near a crack are looked at).
    void compute(const std::vector<Vec2>& x, const Grid& grid, const CrackSegments& segments, KernelType kernel,
                 const StripeOrder& stripes, int threads);
    bool any() const { return !entries.empty(); }

private:
    SegmentIndex index_;
    std::vector<std::uint32_t> particleOf_; // per entry
};

} // namespace shatter::mpm
