#include <shatter/plugin/mpm/ParticleToGrid.h>

#include <shatter/plugin/mpm/CubicRowStencil.h>
#include <shatter/plugin/mpm/TransferTargets.h>

#include <algorithm>
#include <type_traits>

namespace shatter::mpm {

namespace {

// The particles' box (kept up to date by the gather) and the crack points.
Box gridBounds(const SimulationState& s) {
    Box b = s.particleBounds;
    for (const Crack& c : s.cracks)
        for (const Vec2& x : c.points) {
            b.min = b.min.cwiseMin(x);
            b.max = b.max.cwiseMax(x);
        }
    return b;
}

// The grid's clear and the stripe sort, in one parallel region (each parallel region costs a
// wait for the team, long when another process holds a core). The sort is a counting sort by
// blocks: the particles are cut into one block per thread (in index order); each block counts
// its particles per stripe, the counts give every block its place in every stripe (after the
// earlier blocks), and each block writes its indices there. So a stripe lists its particles
// in index order, whatever the thread count.
template <class Spline>
void clearGridAndSortIntoStripes(SimulationState& s) {
    const auto& x = s.particles.x;
    StripeOrder& so = s.stripes;
    const size_t n = x.size(), nodes = s.grid.nodeCount();
    const size_t stripes = size_t(s.grid.nx / StripeOrder::stripeCells + 1);
    const size_t blocks = size_t(std::max(1, s.threads));
    so.stripeOf.resize(n);
    // Block b's count for stripe k, then where it writes there, at blockStart[b·stripes + k].
    so.blockStart.assign(blocks * stripes, 0);
    so.start.assign(stripes + 1, 0);
    so.order.resize(n);
#pragma omp parallel num_threads(s.threads)
    {
#pragma omp for schedule(static)
        for (long b = 0; b < long(blocks); ++b) {
            s.grid.clearField0(nodes * size_t(b) / blocks, nodes * size_t(b + 1) / blocks);
            std::uint32_t* count = &so.blockStart[size_t(b) * stripes];
            // Consecutive particles mostly share a stripe (ParticleSeeder.h), so the run of the
            // current stripe is counted in a register: an increment in memory per particle
            // would wait for the previous one.
            std::uint32_t current = 0, run = 0;
            const double originX = s.grid.origin.x(), invDx = s.grid.invDx;
            for (size_t p = n * size_t(b) / blocks; p < n * size_t(b + 1) / blocks; ++p) {
                const std::uint32_t stripe = StripeOrder::of<Spline>(x[p].x(), originX, invDx);
                so.stripeOf[p] = stripe;
                if (stripe != current) {
                    count[current] += run;
                    current = stripe;
                    run = 0;
                }
                ++run;
            }
            count[current] += run;
        }
#pragma omp single
        {
            std::uint32_t next = 0;
            for (size_t k = 0; k < stripes; ++k) {
                so.start[k] = next;
                for (size_t b = 0; b < blocks; ++b) {
                    const std::uint32_t count = so.blockStart[b * stripes + k];
                    so.blockStart[b * stripes + k] = next;
                    next += count;
                }
            }
            so.start[stripes] = next;
        }
#pragma omp for schedule(static)
        for (long b = 0; b < long(blocks); ++b) {
            std::uint32_t* fill = &so.blockStart[size_t(b) * stripes];
            std::uint32_t current = 0, next = fill[0]; // the same register trick
            for (size_t p = n * size_t(b) / blocks; p < n * size_t(b + 1) / blocks; ++p) {
                if (so.stripeOf[p] != current) {
                    fill[current] = next;
                    current = so.stripeOf[p];
                    next = fill[current];
                }
                so.order[next++] = std::uint32_t(p);
            }
        }
    }
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
struct ParticleShare {
    double m;
    Vec2 c;      // m v + Δt f_body
    Mat2 mC;     // m C
    Mat2 dtVtau; // Δt V⁰ τ
};

// Far from every crack, cubic kernel: field 0 only, a node at a time. Node (i, j) receives
// wx[i]·R_j + wy[j]·K_i with R_j = (row[j], wy[j]·m, 0) and K_i = (column[i], 0, 0).
// m C and Δt V τ come as Double4s in Mat2's (column-major) order: ParticleShare's Mat2s went
// through stack copies before each entry was broadcast.
// `TwoNodes` (the x86-64-v4 copy): the same sums, two nodes of a row per Double8.
template <bool TwoNodes>
[[gnu::always_inline]] inline void scatterFarCubic(Grid& g, const Vec2& xp, double m, const Vec2& c,
                                                   const Double4& mC, const Double4& dtVtau) {
    const CubicRowStencil st(xp - g.origin, g.dx, g.invDx);
    const Double4 wxo = st.wx * st.ox;
    const Double4 columnX = wxo * mC[0] - st.gx * dtVtau[0];
    const Double4 columnY = wxo * mC[1] - st.gx * dtVtau[1];
    const Double4 rowX = st.wy * (c.x() + mC[2] * st.oy) - st.gy * dtVtau[2];
    const Double4 rowY = st.wy * (c.y() + mC[3] * st.oy) - st.gy * dtVtau[3];
    const Double4 rowMass = st.wy * m;
    // R_j and K_i are the columns of (rowX; rowY; rowMass; 0) and (columnX; columnY; 0; 0):
    // two 4 x 4 transposes by shuffles, where building each from lanes took several
    // instructions per node.
    Double4 R[4], K[4];
    transpose4(rowX, rowY, rowMass, Double4{}, R);
    transpose4(columnX, columnY, Double4{}, Double4{}, K);
    const std::size_t nx = std::size_t(g.nx);
    double* row = reinterpret_cast<double*>(&g.node[0][g.index(st.baseX, st.baseY)]);
    if constexpr (TwoNodes) {
        // Lanes 0-3: node i, lanes 4-7: node i + 1, for i = 0 and 2.
        const Double8 wx01 = __builtin_shufflevector(st.wx, st.wx, 0, 0, 0, 0, 1, 1, 1, 1);
        const Double8 wx23 = __builtin_shufflevector(st.wx, st.wx, 2, 2, 2, 2, 3, 3, 3, 3);
        const Double8 K01 = join(K[0], K[1]), K23 = join(K[2], K[3]);
        for (int j = 0; j < 4; ++j, row += 4 * nx) {
            const Double8 Rj = join(R[j], R[j]);
            store8(row, load8(row) + (wx01 * Rj + st.wy[j] * K01));
            store8(row + 8, load8(row + 8) + (wx23 * Rj + st.wy[j] * K23));
        }
    } else {
        for (int j = 0; j < 4; ++j, row += 4 * nx)
            for (int i = 0; i < 4; ++i)
                store4(row + 4 * i, load4(row + 4 * i) + (st.wx[i] * R[j] + st.wy[j] * K[i]));
    }
}

// Any kernel, any particle: the field of each node from the line-crossing test (slot ≥ 0)
// and, near a crack, the mass-weighted displacement and crack normals for crack contact.
template <class Spline>
[[gnu::always_inline]] inline void scatterGeneric(SimulationState& s, size_t p, const ParticleShare& q,
                                                  std::int32_t slot) {
    constexpr int W = Spline::width;
    Grid& g = s.grid;
    const Vec2 xp = s.particles.x[p];
    const Stencil<Spline> st(xp - g.origin, g.invDx);
    Vec2 row[W], column[W];
    double rowMass[W];
    for (int k = 0; k < W; ++k) {
        const double ox = g.origin.x() + (st.baseX + k) * g.dx - xp.x();
        const double oy = g.origin.y() + (st.baseY + k) * g.dx - xp.y();
        row[k] = st.wy[k] * (q.c + q.mC.col(1) * oy) - st.gy[k] * q.dtVtau.col(1);
        column[k] = st.wx[k] * ox * q.mC.col(0) - st.gx[k] * q.dtVtau.col(0);
        rowMass[k] = st.wy[k] * q.m;
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
        return;
    }
    const FieldAssignment::Entry* entry = slot >= 0 ? &s.fields.entries[size_t(slot)] : nullptr;
    const Vec2 mu = q.m * (xp - s.particles.x0[p]);
    for (int j = 0; j < W; ++j) {
        const size_t rowStart = g.index(st.baseX, st.baseY + j);
        for (int i = 0; i < W; ++i) {
            const size_t n = rowStart + size_t(i);
            const int f = entry ? entry->field[size_t(i * W + j)] : 0;
            const double wm = st.wx[i] * rowMass[j];
            const Vec2 momentum = st.wx[i] * row[j] + st.wy[j] * column[i];
            const Vec2 displacement = (st.wx[i] * st.wy[j]) * mu;
            // The pair's share goes to field f, the rest to field 0 (LineCrossing.h).
            const double share = f != 0 ? entry->share[size_t(i * W + j)] : 1;
            Grid::Node& node = g.node[size_t(f)][n];
            node.mass += share * wm;
            node.momentum += share * momentum;
            g.displacement[size_t(f)][n] += share * displacement;
            if (share < 1) {
                Grid::Node& rest = g.node[0][n];
                rest.mass += (1 - share) * wm;
                rest.momentum += (1 - share) * momentum;
                g.displacement[0][n] += (1 - share) * displacement;
            }
            if (entry && entry->segment[size_t(i * W + j)] >= 0)
                g.crackNormal[n] += (share * wm) * s.segments.segment(entry->segment[size_t(i * W + j)]).normal;
        }
    }
}

// The nodes a fixed particle touches (weight > 0) hold still in the grid update.
template <class Spline>
void markFixedNodes(Grid& g, const Vec2& xp) {
    constexpr int W = Spline::width;
    const Stencil<Spline> st(xp - g.origin, g.invDx);
    for (int j = 0; j < W; ++j)
        for (int i = 0; i < W; ++i)
            if (st.wx[i] * st.wy[j] > 0) g.fixedNode[g.index(st.baseX + i, st.baseY + j)] = 1;
}

// Inlined into the stripe loops, so that it is compiled in both of their copies
// (TransferTargets.h). `Lanes` 4 or 8: far particles of the cubic kernel take the Double4
// path, with 8 two nodes at a time; 1: the scalar loops.
template <class Spline, int Lanes>
[[gnu::always_inline]] inline void scatterParticle(SimulationState& s, size_t p, double dt, bool apic) {
    const Particles& P = s.particles;
    ParticleShare q;
    q.m = P.mass[p];
    q.c = q.m * P.v[p] + dt * q.m * s.scene.gravity;
    if (!s.loads.empty()) q.c += dt * s.externalForce[p]; // else zero: not worth reading
    const double dtV = dt * P.volume0[p];
    // -1: far from every crack (FieldAssignment.h)
    const std::int32_t slot = s.fields.slot.empty() ? -1 : s.fields.slot[p];
    bool done = false;
    if constexpr (Lanes > 1 && std::is_same_v<Spline, CubicSpline>) {
        if (slot == -1) {
            // The same products as q.mC and q.dtVtau below, entry by entry.
            scatterFarCubic<Lanes == 8>(s.grid, P.x[p], q.m, q.c, apic ? q.m * load4(P.C[p].data()) : Double4{},
                            dtV * load4(s.stress[p].data()));
            done = true;
        }
    }
    if (!done) {
        q.mC = apic ? Mat2(q.m * P.C[p]) : Mat2::Zero();
        q.dtVtau = dtV * s.stress[p]; // computed by the last gather
        scatterGeneric<Spline>(s, p, q, slot);
    }
    if (P.fixed[p]) markFixedNodes<Spline>(s.grid, P.x[p]);
}

// The particles of one stripe, in order, in the three copies.
template <class Spline, int Lanes>
[[gnu::always_inline]] inline void scatterStripeLoop(SimulationState& s, int stripe, double dt, bool apic) {
    const StripeOrder& so = s.stripes;
    for (std::uint32_t idx = so.start[size_t(stripe)]; idx < so.start[size_t(stripe) + 1]; ++idx)
        scatterParticle<Spline, Lanes>(s, so.order[idx], dt, apic);
}

#if TRANSFER_HAS_X86_64_V4
template <class Spline>
TRANSFER_X86_64_V4 void scatterStripeX86_64_v4(SimulationState& s, int stripe, double dt, bool apic) {
    scatterStripeLoop<Spline, 8>(s, stripe, dt, apic);
}
#endif

template <class Spline>
TRANSFER_X86_64_V3 void scatterStripeX86_64_v3(SimulationState& s, int stripe, double dt, bool apic) {
    scatterStripeLoop<Spline, 4>(s, stripe, dt, apic);
}

template <class Spline>
void scatterStripeGeneric(SimulationState& s, int stripe, double dt, bool apic) {
    scatterStripeLoop<Spline, 1>(s, stripe, dt, apic);
}

// The copy this CPU runs (TransferTargets.h).
template <class Spline>
auto scatterStripeCopy() {
#if TRANSFER_HAS_X86_64_V4
    if (runsX86_64_v4()) return scatterStripeX86_64_v4<Spline>;
#endif
    return runsX86_64_v3() ? scatterStripeX86_64_v3<Spline> : scatterStripeGeneric<Spline>;
}

// The stripes of each colour, those with the most particles first: threads that take the
// next stripe as they finish one then end together (the last stripes are the small ones).
// The order of the stripes does not change the result: two stripes of one colour never
// write the same node.
void orderStripesByLoad(StripeOrder& so) {
    so.heaviestFirst.resize(size_t(so.stripes()));
    for (int k = 0; k < so.stripes(); ++k) so.heaviestFirst[size_t(k)] = k;
    const auto load = [&](int k) { return so.start[size_t(k) + 1] - so.start[size_t(k)]; };
    std::sort(so.heaviestFirst.begin(), so.heaviestFirst.end(), [&](int a, int b) {
        if (a % 2 != b % 2) return a % 2 < b % 2; // even stripes (colour 0), then odd ones
        return load(a) != load(b) ? load(a) > load(b) : a < b;
    });
}

template <class Spline>
void scatter(SimulationState& s, double dt) {
    const bool apic = s.scene.transfer == VelocityTransfer::Apic;
    const auto scatterStripe = scatterStripeCopy<Spline>();
    StripeOrder& so = s.stripes;
    orderStripesByLoad(so);
    const int evens = (so.stripes() + 1) / 2;
#pragma omp parallel num_threads(s.threads)
    for (int colour = 0; colour < 2; ++colour) {
        const int first = colour == 0 ? 0 : evens, last = colour == 0 ? evens : so.stripes();
        // The loop's implicit barrier keeps the colours apart.
#pragma omp for schedule(dynamic, 1)
        for (int k = first; k < last; ++k) scatterStripe(s, so.heaviestFirst[size_t(k)], dt, apic);
    }
}

} // namespace

void prepareGrid(SimulationState& s) {
    const int pad = 3; // covers the cubic stencil (2 cells) with one to spare
    s.grid.clearCrackData(s.fields.nodes); // the last substep's, in its layout
    s.grid.resize(gridBounds(s), s.scene.grid.dx, pad, s.hasCracks() ? Grid::maxFields : 1, s.hasCracks());
    if (s.scene.grid.kernel == KernelType::Cubic)
        clearGridAndSortIntoStripes<CubicSpline>(s);
    else
        clearGridAndSortIntoStripes<QuadraticSpline>(s);
}

void particlesToGrid(SimulationState& s, double dt) {
    if (s.scene.grid.kernel == KernelType::Cubic)
        scatter<CubicSpline>(s, dt);
    else
        scatter<QuadraticSpline>(s, dt);
}

} // namespace shatter::mpm
