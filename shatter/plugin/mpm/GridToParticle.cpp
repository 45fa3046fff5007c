#include <shatter/plugin/mpm/GridToParticle.h>

#include <shatter/plugin/mpm/CubicRowStencil.h>
#include <shatter/plugin/mpm/TransferTargets.h>
#include <shatter/plugin/mpm/TimeStep.h>

#if TRANSFER_HAS_X86_64_V4 // GCC on x86-64: the lane intrinsics below
#include <immintrin.h>
#endif

#include <algorithm>
#include <cmath>
#include <type_traits>
#include <vector>

namespace shatter::mpm {

namespace {

// What the next substep needs of particle p, computed in the gather once its F_E is final
// (at the head of the scatter everything waited for it): its Kirchhoff stress for the
// scatter, and its signal speed c + |v| for the CFL condition, returned.
[[gnu::always_inline]] inline double finishParticle(SimulationState& s, size_t p) {
    const Particles& P = s.particles;
    const ModelConstants& model = s.models[P.material[p]];
    // F_P stays the identity in a model without a return mapping: only the others' need reading.
    const double Jp = hasReturnMapping(model) ? P.Fp[p].determinant() : 1.0;
    s.stress[p] = kirchhoffStress(model, P.Fe[p], Jp);
    return finiteOrInfinite(waveSpeed(model, P.Fe[p], Jp) + P.v[p].norm());
}

// finishParticle for particles p..p+3 (Double4) or p..p+7 (Double8, the x86-64-v4 copy) at
// once, a particle per lane, when they share one corotated material (the common case): the
// same operations in the same order per lane as the scalar code, with the same fused
// multiply-adds, so the same bits (checked lane by lane against finishParticle over 300
// substeps, and by `shatter-bench-mpm --hash`), but four or eight particles' square roots and
// divisions in one instruction each. Separate functions, not inlined into the loop's template:
// the intrinsics need their target. Return false, having written nothing, when they do not
// apply. GCC only: clang 14 has no "x86-64-v3" level for the target attribute, so its copy
// would have no AVX for the intrinsics and Double4 returns; clang builds (the sanitizer run)
// take the scalar code, same bits; so do builds for other CPUs (aarch64).
#if !TRANSFER_HAS_X86_64_V4
bool finishFourCorotated(SimulationState&, size_t, double*) { return false; }
#else
// The lane operations finishCorotated needs beyond the vector extension, per width.
TRANSFER_X86_64_V3 inline Double4 sqrtLanes(const Double4& x) { return _mm256_sqrt_pd(x); }
TRANSFER_X86_64_V3 inline Double4 absLanes(const Double4& x) {
    return _mm256_andnot_pd(_mm256_set1_pd(-0.0), x);
}
TRANSFER_X86_64_V3 inline bool anyBelow(const Double4& x, double bound) {
    return _mm256_movemask_pd(_mm256_cmp_pd(x, _mm256_set1_pd(bound), _CMP_LT_OQ)) != 0;
}
#if TRANSFER_HAS_X86_64_V4
TRANSFER_X86_64_V4 inline Double8 sqrtLanes(const Double8& x) {
    return _mm512_maskz_sqrt_pd(0xff, x); // all lanes (_mm512_sqrt_pd makes GCC 12 warn of an uninitialised value)
}
TRANSFER_X86_64_V4 inline Double8 absLanes(const Double8& x) {
    return _mm512_andnot_pd(_mm512_set1_pd(-0.0), x);
}
TRANSFER_X86_64_V4 inline bool anyBelow(const Double8& x, double bound) {
    return _mm512_cmp_pd_mask(x, _mm512_set1_pd(bound), _CMP_LT_OQ) != 0;
}
#endif

// The entries of four adjacent 2 x 2 matrices at `m` in lanes 0-3 (for Double8, of the next
// four in lanes 4-7): out[e] holds entry e of each.
template <class V>
[[gnu::always_inline]] inline void entriesByLane(const double* m, V out[4]) {
    if constexpr (sizeof(V) == sizeof(Double4)) {
        transpose4(load4(m), load4(m + 4), load4(m + 8), load4(m + 12), out);
    } else {
        Double4 a[4], b[4];
        transpose4(load4(m), load4(m + 4), load4(m + 8), load4(m + 12), a);
        transpose4(load4(m + 16), load4(m + 20), load4(m + 24), load4(m + 28), b);
        for (int e = 0; e < 4; ++e) out[e] = join(a[e], b[e]);
    }
}

// Not always_inline: that would inline the target helpers above into a copy of this template
// for the default target, which GCC refuses; the callers below flatten it instead.
template <class V>
inline bool finishCorotated(SimulationState& s, size_t p, double* signal) {
    constexpr int lanes = int(sizeof(V) / sizeof(double));
    const Particles& P = s.particles;
    const std::uint16_t material = P.material[p];
    for (int q = 1; q < lanes; ++q)
        if (P.material[p + size_t(q)] != material) return false;
    const ModelConstants& model = s.models[material];
    if (model.model != ConstitutiveModelType::Corotated) return false;
    // Lane k of f[e]: entry e (column-major: 00, 10, 01, 11) of particle p + k's F_E.
    V f[4];
    entriesByLane(P.Fe[p].data(), f);
    const V c = f[0] + f[3], sn = f[1] - f[2];
    const V n = sqrtLanes(c * c + sn * sn);
    if (anyBelow(n, 1e-300)) return false; // polarRotation's special case
    const V r00 = c / n, r10 = sn / n, r01 = -sn / n, r11 = c / n;
    const double k = 2 * model.mu; // 2 μ h: h = 1, exactly
    const V a00 = k * (f[0] - r00), a10 = k * (f[1] - r10), a01 = k * (f[2] - r01), a11 = k * (f[3] - r11);
    const V J = f[0] * f[3] - f[1] * f[2];
    const V t = (model.lambda * (J - 1)) * J; // λ h (J − 1) J
    const V tau[4] = {a00 * f[0] + a01 * f[2] + t, a10 * f[0] + a11 * f[2] + t * 0.0, a00 * f[1] + a01 * f[3] + t * 0.0,
                      a10 * f[1] + a11 * f[3] + t};
    for (int half = 0; half < lanes / 4; ++half) {
        Double4 quarter[4], perParticle[4];
        for (int e = 0; e < 4; ++e)
            if constexpr (sizeof(V) == sizeof(Double4))
                quarter[e] = tau[e];
            else
                quarter[e] = half == 0 ? __builtin_shufflevector(tau[e], tau[e], 0, 1, 2, 3)
                                       : __builtin_shufflevector(tau[e], tau[e], 4, 5, 6, 7);
        transpose4(quarter[0], quarter[1], quarter[2], quarter[3], perParticle);
        for (int q = 0; q < 4; ++q) store4(s.stress[p + size_t(4 * half + q)].data(), perParticle[q]);
    }
    // waveSpeed + |v|: lane k of vx, vy is particle p + k's velocity.
    V vx, vy;
    if constexpr (sizeof(V) == sizeof(Double4)) {
        const Double4 v01 = load4(P.v[p].data()), v23 = load4(P.v[p + 2].data());
        vx = __builtin_shufflevector(v01, v23, 0, 2, 4, 6);
        vy = __builtin_shufflevector(v01, v23, 1, 3, 5, 7);
    } else {
        const Double8 v03 = load8(P.v[p].data()), v47 = load8(P.v[p + 4].data());
        vx = __builtin_shufflevector(v03, v47, 0, 2, 4, 6, 8, 10, 12, 14);
        vy = __builtin_shufflevector(v03, v47, 1, 3, 5, 7, 9, 11, 13, 15);
    }
    const V absJ = absLanes(J);
    const V one = V{} + 1.0;
    const V stretch = 1.0 < absJ ? absJ : one;
    // Eigen's squared norm of a Vec2 is a vector multiply and a horizontal add: two rounded
    // squares, never a fused multiply-add, which the empty asm keeps GCC from forming here.
    V vx2 = vx * vx, vy2 = vy * vy;
    asm("" : "+v"(vx2), "+v"(vy2));
    // waveSpeed's product is rounded before the add too (GCC does not fuse it in the scalar code).
    V ws = model.waveSpeed0 * stretch;
    asm("" : "+v"(ws));
    const V speed = ws + sqrtLanes(vx2 + vy2);
    for (int q = 0; q < lanes; ++q) signal[q] = finiteOrInfinite(speed[q]);
    return true;
}

TRANSFER_X86_64_V3 [[gnu::flatten]] bool finishFourCorotated(SimulationState& s, size_t p, double signal[4]) {
    return finishCorotated<Double4>(s, p, signal);
}
#if TRANSFER_HAS_X86_64_V4
TRANSFER_X86_64_V4 [[gnu::flatten]] bool finishEightCorotated(SimulationState& s, size_t p, double signal[8]) {
    return finishCorotated<Double8>(s, p, signal);
}
#endif
#endif

// What a particle reads from the grid: its velocity, velocity gradient ∇v = Σ v ⊗ ∇w and,
// for APIC, B = Σ w v ⊗ o (o = x_i − x_p).
struct GridSample {
    Vec2 v = Vec2::Zero();
    Mat2 gradV = Mat2::Zero(), B = Mat2::Zero();
};

// Any kernel, any particle. Factorised over the axes like the scatter (ParticleToGrid.cpp):
// per row j of nodes, S0 = Σ wx v, S1 = Σ gx v, S2 = Σ wx·ox v; then
//   v += wy S0,  ∇v: col 0 += wy S1, col 1 += gy S0,  B: col 0 += wy S2, col 1 += wy·oy S0.
// The field of each node comes from the line-crossing test when the particle has an entry.
template <class Spline>
[[gnu::always_inline]] inline GridSample sampleGeneric(const SimulationState& s, const Vec2& xp,
                                                      const FieldAssignment::Entry* entry) {
    constexpr int W = Spline::width;
    const Grid& g = s.grid;
    const Stencil<Spline> st(xp - g.origin, g.invDx);
    double wxo[W];
    for (int k = 0; k < W; ++k) wxo[k] = st.wx[k] * (g.origin.x() + (st.baseX + k) * g.dx - xp.x());
    GridSample out;
    for (int j = 0; j < W; ++j) {
        const size_t row = g.index(st.baseX, st.baseY + j);
        Vec2 S0 = Vec2::Zero(), S1 = Vec2::Zero(), S2 = Vec2::Zero();
        for (int i = 0; i < W; ++i) {
            const int f = entry ? entry->field[size_t(i * W + j)] : 0;
            Vec2 vi = g.node[size_t(f)][row + size_t(i)].momentum;
            if (f != 0 && entry->share[size_t(i * W + j)] < 1) { // shared with field 0 (LineCrossing.h)
                const double share = entry->share[size_t(i * W + j)];
                vi = share * vi + (1 - share) * g.node[0][row + size_t(i)].momentum;
            }
            S0 += st.wx[i] * vi;
            S1 += st.gx[i] * vi;
            S2 += wxo[i] * vi;
        }
        const double oy = g.origin.y() + (st.baseY + j) * g.dx - xp.y();
        out.v += st.wy[j] * S0;
        out.gradV.col(0) += st.wy[j] * S1;
        out.gradV.col(1) += st.gy[j] * S0;
        out.B.col(0) += st.wy[j] * S2;
        out.B.col(1) += (st.wy[j] * oy) * S0;
    }
    return out;
}

// What sampleFarCubic reads: GridSample's ∇v and B as Double4s in Mat2's (column-major)
// order, so that the F_E and C updates work on whole matrices.
struct FarSample {
    Vec2 v;
    Double4 gradV, B;
};

// Far from every crack, cubic kernel: the same sums, a node at a time. Node i of a row is
// (vx, vy, m, 0); per row, (S0, S1) accumulate in one Double4 from (v, v), S2 in another.
[[gnu::always_inline]] inline FarSample sampleFarCubic(const Grid& g, const Vec2& xp) {
    const CubicRowStencil st(xp - g.origin, g.dx, g.invDx);
    const Double4 wxo = st.wx * st.ox, wyoy = st.wy * st.oy;
    Double4 vAndGrad0{}, grad1AndB1{}, b0{}; // (v, ∇v col 0), (∇v col 1, B col 1), (B col 0, −)
    for (int j = 0; j < 4; ++j) {
        const double* row = reinterpret_cast<const double*>(&g.node[0][g.index(st.baseX, st.baseY + j)]);
        Double4 s01{}, s2{};
        for (int i = 0; i < 4; ++i) {
            const Double4 node = load4(row + 4 * i);
            s01 += Double4{st.wx[i], st.wx[i], st.gx[i], st.gx[i]} * __builtin_shufflevector(node, node, 0, 1, 0, 1);
            s2 += wxo[i] * node;
        }
        vAndGrad0 += st.wy[j] * s01;
        grad1AndB1 += Double4{st.gy[j], st.gy[j], wyoy[j], wyoy[j]} * __builtin_shufflevector(s01, s01, 0, 1, 0, 1);
        b0 += st.wy[j] * s2;
    }
    // B is only used under APIC, so GCC sank its sums behind the caller's `apic` test and
    // kept the 16 node loads for it in stack slots; an empty asm makes them be summed here,
    // while the nodes are in registers (same operations, so the same bits).
    asm("" : "+x"(b0));
    return {Vec2(vAndGrad0[0], vAndGrad0[1]), __builtin_shufflevector(vAndGrad0, grad1AndB1, 2, 3, 4, 5),
            __builtin_shufflevector(b0, grad1AndB1, 0, 1, 6, 7)};
}

// F_E ← (I + Δt ∇v) F_E and C ← B / inertia of a far particle, whole matrices per Double4,
// the same operations per entry as the Eigen expressions in gatherParticle (so the same
// bits): M = I + Δt ∇v, then column j of M F_E is M₀ F_E(0, j) + M₁ F_E(1, j).
[[gnu::always_inline]] inline Vec2 updateFarCubic(SimulationState& s, size_t p, double dt, bool apic,
                                                  double inverseInertia) {
    Particles& P = s.particles;
    const FarSample sample = sampleFarCubic(s.grid, P.x[p]);
    const Double4 m = dt * sample.gradV + Double4{1, 0, 0, 1};
    const Double4 fe = load4(P.Fe[p].data());
    store4(P.Fe[p].data(), __builtin_shufflevector(m, m, 0, 1, 0, 1) * __builtin_shufflevector(fe, fe, 0, 0, 2, 2) +
                               __builtin_shufflevector(m, m, 2, 3, 2, 3) * __builtin_shufflevector(fe, fe, 1, 1, 3, 3));
    store4(P.C[p].data(), apic ? sample.B * inverseInertia : Double4{});
    return sample.v;
}

#if TRANSFER_HAS_X86_64_V4 // the pair gather, only in the x86-64-v4 copy (clang builds have none)
// Lane patterns of the pair gather: (p, p, q, q, p', p', q', q') and (p, p, p, p, p', p', p', p')
// with p = a[i], q = b[i], primes the second particle's (lanes 4-7).
template <int i>
[[gnu::always_inline]] inline Double8 interleave(const Double8& a, const Double8& b) {
    return __builtin_shufflevector(a, b, i, i, 8 + i, 8 + i, 4 + i, 4 + i, 12 + i, 12 + i);
}
template <int i>
[[gnu::always_inline]] inline Double8 spread(const Double8& a) {
    return __builtin_shufflevector(a, a, i, i, i, i, 4 + i, 4 + i, 4 + i, 4 + i);
}

// One row j of sampleFarCubic for both particles of a pair.
template <int j>
[[gnu::always_inline]] inline void samplePairRow(const Grid& g, const CubicRowStencilPair& st, const Double8 weight[4],
                                                 const Double8 weightO[4], const Double8& wyoy, Double8& vAndGrad0,
                                                 Double8& grad1AndB1, Double8& b0) {
    const double* rowA = reinterpret_cast<const double*>(&g.node[0][g.index(st.baseXa, st.baseYa + j)]);
    const double* rowB = reinterpret_cast<const double*>(&g.node[0][g.index(st.baseXb, st.baseYb + j)]);
    Double8 s01{}, s2{};
    for (int i = 0; i < 4; ++i) {
        const Double8 node = join(load4(rowA + 4 * i), load4(rowB + 4 * i));
        s01 += weight[i] * __builtin_shufflevector(node, node, 0, 1, 0, 1, 4, 5, 4, 5);
        s2 += weightO[i] * node;
    }
    const Double8 wyj = spread<j>(st.wy);
    vAndGrad0 += wyj * s01;
    grad1AndB1 += interleave<j>(st.gy, wyoy) * __builtin_shufflevector(s01, s01, 0, 1, 0, 1, 4, 5, 4, 5);
    b0 += wyj * s2;
}

// sampleFarCubic and updateFarCubic for particles p and p + 1 at once (the x86-64-v4 copy):
// lanes 0-3 of each Double8 are particle p's Double4, lanes 4-7 particle p + 1's, with the
// same operations per lane, so the same bits. Their F_E and C are adjacent in memory. Writes
// their velocities to v.
[[gnu::always_inline]] inline void updateFarCubicPair(SimulationState& s, size_t p, double dt, bool apic,
                                                      double inverseInertia, Vec2 v[2]) {
    Particles& P = s.particles;
    const Grid& g = s.grid;
    const CubicRowStencilPair st(P.x[p] - g.origin, P.x[p + 1] - g.origin, g.dx, g.invDx);
    const Double8 wxo = st.wx * st.ox, wyoy = st.wy * st.oy;
    // Per node i of a row: (wx, wx, gx, gx) and wx·ox, of each particle.
    const Double8 weight[4] = {interleave<0>(st.wx, st.gx), interleave<1>(st.wx, st.gx), interleave<2>(st.wx, st.gx),
                               interleave<3>(st.wx, st.gx)};
    const Double8 weightO[4] = {spread<0>(wxo), spread<1>(wxo), spread<2>(wxo), spread<3>(wxo)};
    Double8 vAndGrad0{}, grad1AndB1{}, b0{};
    samplePairRow<0>(g, st, weight, weightO, wyoy, vAndGrad0, grad1AndB1, b0);
    samplePairRow<1>(g, st, weight, weightO, wyoy, vAndGrad0, grad1AndB1, b0);
    samplePairRow<2>(g, st, weight, weightO, wyoy, vAndGrad0, grad1AndB1, b0);
    samplePairRow<3>(g, st, weight, weightO, wyoy, vAndGrad0, grad1AndB1, b0);
    asm("" : "+v"(b0)); // as in sampleFarCubic
    const Double8 gradV = __builtin_shufflevector(vAndGrad0, grad1AndB1, 2, 3, 8, 9, 6, 7, 12, 13);
    const Double8 B = __builtin_shufflevector(b0, grad1AndB1, 0, 1, 10, 11, 4, 5, 14, 15);
    const Double8 m = dt * gradV + Double8{1, 0, 0, 1, 1, 0, 0, 1};
    const Double8 fe = load8(P.Fe[p].data());
    store8(P.Fe[p].data(), __builtin_shufflevector(m, m, 0, 1, 0, 1, 4, 5, 4, 5) *
                                   __builtin_shufflevector(fe, fe, 0, 0, 2, 2, 4, 4, 6, 6) +
                               __builtin_shufflevector(m, m, 2, 3, 2, 3, 6, 7, 6, 7) *
                                   __builtin_shufflevector(fe, fe, 1, 1, 3, 3, 5, 5, 7, 7));
    store8(P.C[p].data(), apic ? B * inverseInertia : Double8{});
    v[0] = Vec2(vAndGrad0[0], vAndGrad0[1]);
    v[1] = Vec2(vAndGrad0[4], vAndGrad0[5]);
}
#endif

// The end of a particle's gather, once its velocity v from the grid is known and its F_E and
// C are updated: plasticity, colliders, the position.
// `colliders`: which of s.scene.colliders may touch the particle (collidersTouching).
[[gnu::always_inline]] inline void moveParticle(SimulationState& s, size_t p, Vec2 v, double dt,
                                                std::uint64_t colliders) {
    Particles& P = s.particles;
    const Vec2 xp = P.x[p];
    returnToYieldSurface(s.models[P.material[p]], P.Fe[p], P.Fp[p]);
    if (P.fixed[p]) {
        v.setZero();
        P.C[p].setZero();
    } else {
        if (anyToTest(colliders, s.scene.colliders)) {
            // Copies for the (virtual) calls, which take addresses: so that v and xp can stay
            // in registers on the common path, where they were kept on the stack.
            const Vec2 at = xp;
            Vec2 projected = v;
            for (size_t k = 0; k < s.scene.colliders.size(); ++k)
                if (mustTest(colliders, k)) s.scene.colliders[k]->project(at, projected);
            v = projected;
        }
        P.x[p] = xp + dt * v;
    }
    P.v[p] = v;
}

// Updates the particle's velocity, C, F_E and position; finishParticle then gives what the
// next substep needs. Inlined into the range loops, so that it is compiled in each of their
// copies (TransferTargets.h). `Lanes` 4 or 8: far particles of the cubic kernel take the
// Double4 path; 1: the scalar loops.
template <class Spline, int Lanes>
[[gnu::always_inline]] inline void gatherParticle(SimulationState& s, size_t p, double dt, bool apic,
                                                    double inverseInertia, std::uint64_t colliders) {
    Particles& P = s.particles;
    const Vec2 xp = P.x[p];
    const std::int32_t slot = s.fields.slot.empty() ? -1 : s.fields.slot[p];
    const FieldAssignment::Entry* entry = slot >= 0 ? &s.fields.entries[size_t(slot)] : nullptr;
    Vec2 v;
    bool far = false;
    if constexpr (Lanes > 1 && std::is_same_v<Spline, CubicSpline>) {
        if (!entry) {
            v = updateFarCubic(s, p, dt, apic, inverseInertia);
            far = true;
        }
    }
    if (!far) {
        const GridSample sample = sampleGeneric<Spline>(s, xp, entry);
        P.Fe[p] = (Mat2::Identity() + dt * sample.gradV) * P.Fe[p];
        P.C[p] = apic ? Mat2(sample.B * inverseInertia) : Mat2::Zero();
        v = sample.v;
    }
    moveParticle(s, p, v, dt, colliders);
}

// Gathers particles [first, last): with `Lanes` 8, two far particles of the cubic kernel at a
// time where both are far.
template <class Spline, int Lanes>
[[gnu::always_inline]] inline void gatherParticles(SimulationState& s, size_t first, size_t last, double dt,
                                                     bool apic, double inverseInertia, std::uint64_t colliders) {
    for (size_t p = first; p < last;) {
#if TRANSFER_HAS_X86_64_V4
        if constexpr (Lanes == 8 && std::is_same_v<Spline, CubicSpline>) {
            const auto far = [&](size_t q) { return s.fields.slot.empty() || s.fields.slot[q] < 0; };
            if (p + 1 < last && far(p) && far(p + 1)) {
                Vec2 v[2];
                updateFarCubicPair(s, p, dt, apic, inverseInertia, v);
                Particles& P = s.particles;
                const auto plain = [&](size_t q) { return !P.fixed[q] && !hasReturnMapping(s.models[P.material[q]]); };
                if (!anyToTest(colliders, s.scene.colliders) && plain(p) && plain(p + 1)) {
                    // moveParticle of both, their positions and velocities adjacent in memory:
                    // the same fused multiply-add per entry.
                    const Double4 both{v[0].x(), v[0].y(), v[1].x(), v[1].y()};
                    store4(P.x[p].data(), load4(P.x[p].data()) + dt * both);
                    store4(P.v[p].data(), both);
                } else {
                    moveParticle(s, p, v[0], dt, colliders);
                    moveParticle(s, p + 1, v[1], dt, colliders);
                }
                p += 2;
                continue;
            }
        }
#endif
        gatherParticle<Spline, Lanes>(s, p, dt, apic, inverseInertia, colliders);
        ++p;
    }
}

// The fastest signal and the bounding box of some particles.
struct Summary {
    double fastest = 0;
    Box bounds{Vec2::Constant(INFINITY), Vec2::Constant(-INFINITY)};

    void add(double signal, const Vec2& x) { add(signal, Box{x, x}); }
    void add(double signal, const Box& box) {
        fastest = std::max(fastest, signal);
        bounds.min = bounds.min.cwiseMin(box.min);
        bounds.max = bounds.max.cwiseMax(box.max);
    }
};

// Particles per chunk: the unit of the gather's parallel loop and of SimulationState::chunkBounds.
constexpr size_t chunkSize = 512;

// Particles [first, last) of chunk k, in the three copies.
template <class Spline, int Lanes>
[[gnu::always_inline]] inline Summary gatherRangeLoop(SimulationState& s, size_t k, size_t first, size_t last,
                                                      double dt, bool apic, double inverseInertia) {
    // Most chunks are far from every obstacle and skip the colliders altogether. The chunk's
    // box before this gather moves it is the one the last particle update recorded.
    const std::uint64_t colliders = collidersTouching(s.scene.colliders, s.chunkBounds[k]);
    Summary out;
    // In batches: first the gathers of a few particles, then their stresses. The stress of one
    // particle (a square root and divisions at the end of a chain that starts at its grid
    // loads) is short independent work per particle when done in a row, so the processor
    // overlaps the latencies of several particles; right after each gather it stalled the
    // loop (perf: most of the gather's samples sat on that square root and division).
    constexpr size_t batch = 16;
    for (size_t b = first; b < last; b += batch) {
        const size_t end = std::min(last, b + batch);
        gatherParticles<Spline, Lanes>(s, b, end, dt, apic, inverseInertia, colliders);
        for (size_t p = b; p < end;) {
#if TRANSFER_HAS_X86_64_V4
            if constexpr (Lanes == 8) {
                double signal[8];
                if (p + 8 <= end && finishEightCorotated(s, p, signal)) {
                    for (int q = 0; q < 8; ++q) out.add(signal[q], s.particles.x[p + size_t(q)]);
                    p += 8;
                    continue;
                }
            }
#endif
            if constexpr (Lanes > 1) {
                double signal[4];
                if (p + 4 <= end && finishFourCorotated(s, p, signal)) {
                    for (int q = 0; q < 4; ++q) out.add(signal[q], s.particles.x[p + size_t(q)]);
                    p += 4;
                    continue;
                }
            }
            out.add(finishParticle(s, p), s.particles.x[p]);
            ++p;
        }
    }
    return out;
}

#if TRANSFER_HAS_X86_64_V4
template <class Spline>
TRANSFER_X86_64_V4 Summary gatherRangeX86_64_v4(SimulationState& s, size_t k, size_t first, size_t last, double dt,
                                                bool apic, double inverseInertia) {
    return gatherRangeLoop<Spline, 8>(s, k, first, last, dt, apic, inverseInertia);
}
#endif

template <class Spline>
TRANSFER_X86_64_V3 Summary gatherRangeX86_64_v3(SimulationState& s, size_t k, size_t first, size_t last, double dt,
                                                bool apic, double inverseInertia) {
    return gatherRangeLoop<Spline, 4>(s, k, first, last, dt, apic, inverseInertia);
}

template <class Spline>
Summary gatherRangeGeneric(SimulationState& s, size_t k, size_t first, size_t last, double dt, bool apic,
                           double inverseInertia) {
    return gatherRangeLoop<Spline, 1>(s, k, first, last, dt, apic, inverseInertia);
}

// The copy this CPU runs (TransferTargets.h).
template <class Spline>
auto gatherRangeCopy() {
#if TRANSFER_HAS_X86_64_V4
    if (runsX86_64_v4()) return gatherRangeX86_64_v4<Spline>;
#endif
    return runsX86_64_v3() ? gatherRangeX86_64_v3<Spline> : gatherRangeGeneric<Spline>;
}

// Runs `range(k, first, last)` over the particles in chunks k, in parallel, and stores the
// combined summary and each chunk's box in s.
template <class Range>
void summariseChunks(SimulationState& s, const Range& range) {
    const size_t n = s.particles.size();
    const long chunks = long((n + chunkSize - 1) / chunkSize);
    std::vector<Summary> parts(static_cast<size_t>(chunks));
    // Dynamic: the particles near a crack (the slower, generic transfer) sit in a few chunks,
    // since particles are numbered column by column; results do not depend on the schedule.
#pragma omp parallel for schedule(dynamic, 1) num_threads(s.threads)
    for (long k = 0; k < chunks; ++k) {
        const size_t first = size_t(k) * chunkSize;
        parts[size_t(k)] = range(size_t(k), first, std::min(n, first + chunkSize));
    }
    Summary all;
    s.chunkBounds.resize(parts.size());
    for (size_t k = 0; k < parts.size(); ++k) {
        all.add(parts[k].fastest, parts[k].bounds);
        s.chunkBounds[k] = parts[k].bounds;
    }
    s.fastestSignal = all.fastest;
    s.particleBounds = all.bounds;
}

template <class Spline>
void gather(SimulationState& s, double dt) {
    const bool apic = s.scene.transfer == VelocityTransfer::Apic;
    const double inverseInertia = apicInverseInertia(s.scene.grid.kernel) * s.grid.invDx * s.grid.invDx;
    const auto gatherRange = gatherRangeCopy<Spline>();
    summariseChunks(s, [&](size_t k, size_t first, size_t last) {
        return gatherRange(s, k, first, last, dt, apic, inverseInertia);
    });
}

} // namespace

void updateAfterParticleEdit(SimulationState& s) {
    // The per-particle arrays follow the particle count (particles may have been added).
    s.stress.resize(s.particles.size());
    s.externalForce.resize(s.particles.size(), Vec2::Zero());
    summariseChunks(s, [&](size_t, size_t first, size_t last) {
        Summary out;
        for (size_t p = first; p < last; ++p) out.add(finishParticle(s, p), s.particles.x[p]);
        return out;
    });
}

void gridToParticles(SimulationState& s, double dt) {
    if (s.scene.grid.kernel == KernelType::Cubic)
        gather<CubicSpline>(s, dt);
    else
        gather<QuadraticSpline>(s, dt);
}

} // namespace shatter::mpm
