#include "plugin/mpm/ParticleToGrid.h"

#include <algorithm>

namespace shatter::mpm {

namespace {

Box particleBounds(const SimulationState& s) {
    Box b{Vec2::Constant(1e300), Vec2::Constant(-1e300)};
    for (const Vec2& x : s.particles.x) {
        b.min = b.min.cwiseMin(x);
        b.max = b.max.cwiseMax(x);
    }
    for (const Crack& c : s.cracks)
        for (const Vec2& x : c.points) {
            b.min = b.min.cwiseMin(x);
            b.max = b.max.cwiseMax(x);
        }
    return b;
}

template <class Spline>
void sortIntoStripes(SimulationState& s) {
    const auto& x = s.particles.x;
    StripeOrder& so = s.stripes;
    const int stripes = s.grid.nx / StripeOrder::stripeCells + 1;
    std::vector<int> stripeOf(x.size());
    so.start.assign(size_t(stripes) + 1, 0);
    double w[Spline::width], g[Spline::width];
    for (size_t p = 0; p < x.size(); ++p) {
        const int baseX = Spline::stencil((x[p].x() - s.grid.origin.x()) * s.grid.invDx, w, g);
        stripeOf[p] = baseX / StripeOrder::stripeCells;
        ++so.start[size_t(stripeOf[p]) + 1];
    }
    for (int k = 0; k < stripes; ++k) so.start[size_t(k) + 1] += so.start[size_t(k)];
    so.order.resize(x.size());
    std::vector<std::uint32_t> fill(so.start.begin(), so.start.end() - 1);
    for (size_t p = 0; p < x.size(); ++p) so.order[fill[size_t(stripeOf[p])]++] = std::uint32_t(p);
}

// The work of one particle, with everything that does not depend on the node hoisted out
// of the 4 x 4 loop (this loop is most of the solver's time).
template <class Spline>
void scatterParticle(SimulationState& s, size_t p, bool apic, bool crackData) {
    constexpr int W = Spline::width;
    const Particles& P = s.particles;
    Grid& g = s.grid;
    const Vec2 xp = P.x[p];
    const Stencil<Spline> st(xp - g.origin, g.invDx);
    const double m = P.mass[p];
    const Vec2 mv = m * P.v[p];
    const Mat2 mC = apic ? Mat2(m * P.C[p]) : Mat2::Zero();
    // Stress is evaluated here rather than in a pass of its own: one sweep over the particles.
    const Mat2 Vtau = P.volume0[p] * kirchhoffStress(s.models[P.material[p]], P.Fe[p], P.Fp[p].determinant());
    const Vec2 fBody = s.externalForce[p] + m * s.scene.gravity;
    const Vec2 mu = m * (xp - P.x0[p]);
    const std::int32_t slot = s.fields.slot.empty() ? -1 : s.fields.slot[p];
    const FieldAssignment::Entry* entry = slot >= 0 ? &s.fields.entries[size_t(slot)] : nullptr;
    // Per-axis pieces: node offsets times the affine columns, stress times the slopes.
    Vec2 affineX[W], affineY[W], stressX[W], stressY[W];
    for (int k = 0; k < W; ++k) {
        affineX[k] = mC.col(0) * (g.origin.x() + (st.baseX + k) * g.dx - xp.x());
        affineY[k] = mC.col(1) * (g.origin.y() + (st.baseY + k) * g.dx - xp.y());
        stressX[k] = Vtau.col(0) * st.gx[k];
        stressY[k] = Vtau.col(1) * st.gy[k];
    }
    for (int j = 0; j < W; ++j) {
        const size_t row = g.index(st.baseX, st.baseY + j);
        for (int i = 0; i < W; ++i) {
            const double w = st.wx[i] * st.wy[j];
            const int f = entry ? entry->field[size_t(i * W + j)] : 0;
            Grid::Node& node = g.node[f][row + size_t(i)];
            node.mass += w * m;
            node.momentum += w * (mv + affineX[i] + affineY[j]);
            node.force += w * fBody - stressX[i] * st.wy[j] - stressY[j] * st.wx[i];
            if (crackData) {
                const size_t n = row + size_t(i);
                g.displacement[f][n] += w * mu;
                if (entry && entry->segment[size_t(i * W + j)] >= 0)
                    g.crackNormal[n] += (w * m) * s.segments.segment(entry->segment[size_t(i * W + j)]).normal;
            }
        }
    }
    if (P.fixed[p])
        for (int j = 0; j < W; ++j)
            for (int i = 0; i < W; ++i)
                if (st.wx[i] * st.wy[j] > 0) g.fixedNode[g.index(st.baseX + i, st.baseY + j)] = 1;
}

template <class Spline>
void scatter(SimulationState& s) {
    const bool apic = s.scene.transfer == VelocityTransfer::Apic;
    const bool crackData = s.hasCracks();
    const StripeOrder& so = s.stripes;
    const int stripes = so.stripes();
    for (int colour = 0; colour < 2; ++colour) {
        const int count = (stripes - colour + 1) / 2;
#pragma omp parallel for schedule(dynamic, 1) num_threads(s.threads)
        for (int k = 0; k < count; ++k) {
            const int stripe = colour + 2 * k;
            for (std::uint32_t idx = so.start[size_t(stripe)]; idx < so.start[size_t(stripe) + 1]; ++idx)
                scatterParticle<Spline>(s, so.order[idx], apic, crackData);
        }
    }
}

} // namespace

void prepareGrid(SimulationState& s) {
    const int pad = 3; // covers the cubic stencil (2 cells) with one to spare
    s.grid.reset(particleBounds(s), s.scene.grid.dx, pad, s.hasCracks() ? Grid::maxFields : 1, s.hasCracks());
    if (s.scene.grid.kernel == KernelType::Cubic)
        sortIntoStripes<CubicSpline>(s);
    else
        sortIntoStripes<QuadraticSpline>(s);
}

void particlesToGrid(SimulationState& s) {
    if (s.scene.grid.kernel == KernelType::Cubic)
        scatter<CubicSpline>(s);
    else
        scatter<QuadraticSpline>(s);
}

} // namespace shatter::mpm
