#include "plugin/mpm/GridToParticle.h"

#include "plugin/mpm/TimeStep.h"

#include <algorithm>

namespace shatter::mpm {

namespace {

// Returns the particle's signal speed for the next substep's CFL condition.
template <class Spline>
double gatherParticle(SimulationState& s, size_t p, double dt, bool apic, double inverseInertia) {
    constexpr int W = Spline::width;
    Particles& P = s.particles;
    const Grid& g = s.grid;
    const Vec2 xp = P.x[p];
    const Stencil<Spline> st(xp - g.origin, g.invDx);
    const std::int32_t slot = s.fields.slot.empty() ? -1 : s.fields.slot[p];
    const FieldAssignment::Entry* entry = slot >= 0 ? &s.fields.entries[size_t(slot)] : nullptr;
    double ox[W], oy[W]; // node offsets from the particle
    for (int k = 0; k < W; ++k) {
        ox[k] = g.origin.x() + (st.baseX + k) * g.dx - xp.x();
        oy[k] = g.origin.y() + (st.baseY + k) * g.dx - xp.y();
    }
    Vec2 v = Vec2::Zero();
    Mat2 gradV = Mat2::Zero(), B = Mat2::Zero();
    for (int j = 0; j < W; ++j) {
        const size_t row = g.index(st.baseX, st.baseY + j);
        for (int i = 0; i < W; ++i) {
            const int f = entry ? entry->field[size_t(i * W + j)] : 0;
            const Vec2& vi = g.node[f][row + size_t(i)].momentum;
            const double w = st.wx[i] * st.wy[j];
            const Vec2 wv = w * vi;
            v += wv;
            gradV.col(0) += vi * (st.gx[i] * st.wy[j]);
            gradV.col(1) += vi * (st.wx[i] * st.gy[j]);
            B.col(0) += wv * ox[i];
            B.col(1) += wv * oy[j];
        }
    }
    const ModelConstants& model = s.models[P.material[p]];
    P.Fe[p] = (Mat2::Identity() + dt * gradV) * P.Fe[p];
    returnToYieldSurface(model, P.Fe[p], P.Fp[p]);
    P.C[p] = apic ? Mat2(B * inverseInertia) : Mat2::Zero();
    if (P.fixed[p]) {
        v.setZero();
        P.C[p].setZero();
    } else {
        for (const auto& collider : s.scene.colliders) collider->project(xp, v);
        P.x[p] = xp + dt * v;
    }
    P.v[p] = v;
    return finiteOrInfinite(signalSpeed(model, P.Fe[p], P.Fp[p], v));
}

template <class Spline>
void gather(SimulationState& s, double dt) {
    const bool apic = s.scene.transfer == VelocityTransfer::Apic;
    const double inverseInertia = apicInverseInertia(s.scene.grid.kernel) * s.grid.invDx * s.grid.invDx;
    const long n = long(s.particles.size());
    double fastest = 0;
#pragma omp parallel for schedule(static) reduction(max : fastest) num_threads(s.threads)
    for (long p = 0; p < n; ++p) fastest = std::max(fastest, gatherParticle<Spline>(s, size_t(p), dt, apic, inverseInertia));
    s.fastestSignal = fastest;
}

} // namespace

void gridToParticles(SimulationState& s, double dt) {
    if (s.scene.grid.kernel == KernelType::Cubic)
        gather<CubicSpline>(s, dt);
    else
        gather<QuadraticSpline>(s, dt);
}

} // namespace shatter::mpm
