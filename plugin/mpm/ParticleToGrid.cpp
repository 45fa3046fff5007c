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
    for (size_t p = 0; p < x.size(); ++p) {
        const int baseX = Spline::first((x[p].x() - s.grid.origin.x()) * s.grid.invDx);
        stripeOf[p] = baseX / StripeOrder::stripeCells;
        ++so.start[size_t(stripeOf[p]) + 1];
    }
    for (int k = 0; k < stripes; ++k) so.start[size_t(k) + 1] += so.start[size_t(k)];
    so.order.resize(x.size());
    std::vector<std::uint32_t> fill(so.start.begin(), so.start.end() - 1);
    for (size_t p = 0; p < x.size(); ++p) so.order[fill[size_t(stripeOf[p])]++] = std::uint32_t(p);
}

// The work of one particle. This loop is most of the solver's time, so everything that does
// not depend on the node is hoisted out of the W x W loop, and what a node receives is
// factorised over the two axes. With w = wx[i]·wy[j], ∇w = (gx[i]·wy[j], wx[i]·gy[j]) and
// o = x_i − x_p, node (i, j) receives
//   mass      w·m
//   momentum  w·(m v + Δt f_body) + w·m C o − Δt V τ ∇w          (APIC; C = 0 under PIC)
//           = wx[i]·row[j] + wy[j]·column[i],
//   row[j]    = wy[j]·(m v + Δt f_body + m C₁ o_y[j]) − Δt gy[j]·V τ₁,
//   column[i] = wx[i]·m C₀ o_x[i] − Δt gx[i]·V τ₀          (C₀, τ₀: first columns).
template <class Spline>
void scatterParticle(SimulationState& s, size_t p, double dt, bool apic) {
    constexpr int W = Spline::width;
    const Particles& P = s.particles;
    Grid& g = s.grid;
    const Vec2 xp = P.x[p];
    const Stencil<Spline> st(xp - g.origin, g.invDx);
    const double m = P.mass[p];
    const Mat2 mC = apic ? Mat2(m * P.C[p]) : Mat2::Zero();
    // Stress is evaluated here rather than in a pass of its own: one sweep over the particles.
    const Mat2 dtVtau = (dt * P.volume0[p]) * kirchhoffStress(s.models[P.material[p]], P.Fe[p], P.Fp[p].determinant());
    const Vec2 c = m * P.v[p] + dt * (s.externalForce[p] + m * s.scene.gravity);
    const std::int32_t slot = s.fields.slot.empty() ? -1 : s.fields.slot[p];
    Vec2 row[W], column[W];
    double rowMass[W];
    for (int k = 0; k < W; ++k) {
        const double ox = g.origin.x() + (st.baseX + k) * g.dx - xp.x();
        const double oy = g.origin.y() + (st.baseY + k) * g.dx - xp.y();
        row[k] = st.wy[k] * (c + mC.col(1) * oy) - st.gy[k] * dtVtau.col(1);
        column[k] = st.wx[k] * ox * mC.col(0) - st.gx[k] * dtVtau.col(0);
        rowMass[k] = st.wy[k] * m;
    }
    if (slot == -1) {
        // Far from every crack: field 0 only, and no displacement (crack contact never
        // looks at the nodes this particle reaches).
        Grid::Node* nodes = g.node[0].data();
        for (int j = 0; j < W; ++j) {
            Grid::Node* n = nodes + g.index(st.baseX, st.baseY + j);
            for (int i = 0; i < W; ++i) {
                n[i].mass += st.wx[i] * rowMass[j];
                n[i].momentum += st.wx[i] * row[j] + st.wy[j] * column[i];
            }
        }
    } else {
        // Near a crack: the field comes from the line-crossing test, and the mass-weighted
        // displacement and crack normals feed crack contact.
        const FieldAssignment::Entry* entry = slot >= 0 ? &s.fields.entries[size_t(slot)] : nullptr;
        const Vec2 mu = m * (xp - P.x0[p]);
        for (int j = 0; j < W; ++j) {
            const size_t rowStart = g.index(st.baseX, st.baseY + j);
            for (int i = 0; i < W; ++i) {
                const size_t n = rowStart + size_t(i);
                const int f = entry ? entry->field[size_t(i * W + j)] : 0;
                const double wm = st.wx[i] * rowMass[j];
                Grid::Node& node = g.node[size_t(f)][n];
                node.mass += wm;
                node.momentum += st.wx[i] * row[j] + st.wy[j] * column[i];
                g.displacement[size_t(f)][n] += (st.wx[i] * st.wy[j]) * mu;
                if (entry && entry->segment[size_t(i * W + j)] >= 0)
                    g.crackNormal[n] += wm * s.segments.segment(entry->segment[size_t(i * W + j)]).normal;
            }
        }
    }
    if (P.fixed[p])
        for (int j = 0; j < W; ++j)
            for (int i = 0; i < W; ++i)
                if (st.wx[i] * st.wy[j] > 0) g.fixedNode[g.index(st.baseX + i, st.baseY + j)] = 1;
}

template <class Spline>
void scatter(SimulationState& s, double dt) {
    const bool apic = s.scene.transfer == VelocityTransfer::Apic;
    const StripeOrder& so = s.stripes;
    const int stripes = so.stripes();
    for (int colour = 0; colour < 2; ++colour) {
        const int count = (stripes - colour + 1) / 2;
#pragma omp parallel for schedule(dynamic, 1) num_threads(s.threads)
        for (int k = 0; k < count; ++k) {
            const int stripe = colour + 2 * k;
            for (std::uint32_t idx = so.start[size_t(stripe)]; idx < so.start[size_t(stripe) + 1]; ++idx)
                scatterParticle<Spline>(s, so.order[idx], dt, apic);
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

void particlesToGrid(SimulationState& s, double dt) {
    if (s.scene.grid.kernel == KernelType::Cubic)
        scatter<CubicSpline>(s, dt);
    else
        scatter<QuadraticSpline>(s, dt);
}

} // namespace shatter::mpm
