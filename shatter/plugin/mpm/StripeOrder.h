#pragma once
#include <shatter/plugin/mpm/BSpline.h>

#include <cstdint>
#include <vector>

namespace shatter::mpm {

// Particles grouped into vertical stripes of the grid (by the first node of their stencil)
// so that the particle-to-grid scatter runs in parallel without races: between two stripes of
// one colour (even or odd) lies a stripe of the other colour, at least W − 1 cells wide for a
// stencil of W nodes, so they never write the same node. Within a stripe particles keep their
// index order, so every node sums its contributions in the same order whatever the number of
// threads: results are bit-identical for any thread count. Narrow stripes make many of them,
// which the threads share more evenly.
struct StripeOrder {
    static constexpr int stripeCells = 4; // >= the widest stencil (4 nodes) − 1
    std::vector<std::uint32_t> order;     // particle indices, stripe by stripe
    std::vector<std::uint32_t> start;     // stripe s is order[start[s], start[s + 1])
    // Scratch space of the sort and the scatter (ParticleToGrid.cpp), kept to save allocating
    // it every substep.
    std::vector<std::uint32_t> stripeOf, blockStart;
    std::vector<int> heaviestFirst;
    int stripes() const { return int(start.size()) - 1; }

    // The stripe of a particle at x (m) on a grid whose node 0 is at originX: that of the
    // first node of its stencil. Non-decreasing in x.
    template <class Spline>
    static std::uint32_t of(double x, double originX, double invDx) {
        return std::uint32_t(Spline::first((x - originX) * invDx) / stripeCells);
    }
};

} // namespace shatter::mpm
