#include <shatter/plugin/mpm/CrackAdvection.h>

#include <cstdint>

namespace shatter::mpm {

Vec2 crackPointNormal(const Crack& c, size_t k) {
    const auto& pts = c.points;
    Vec2 n = Vec2::Zero();
    if (k > 0) n += leftNormal(pts[k] - pts[k - 1]).normalized();
    if (k + 1 < pts.size()) n += leftNormal(pts[k + 1] - pts[k]).normalized();
    return n.normalized();
}

namespace {

// Nodes without mass in the field used are skipped and the weights renormalised, so a crack
// point at the outline of the body moves with the material rather than slowing down.
template <class Spline>
Vec2 centreOfMassVelocity(const Grid& g, const Vec2& x) {
    constexpr int W = Spline::width;
    const Stencil<Spline> st(x - g.origin, g.invDx);
    Vec2 sum = Vec2::Zero();
    double weight = 0;
    for (int i = 0; i < W; ++i)
        for (int j = 0; j < W; ++j) {
            const size_t n = g.index(st.baseX + i, st.baseY + j);
            double m = 0;
            Vec2 p = Vec2::Zero();
            for (int f = 0; f < g.fields; ++f) {
                m += g.node[f][n].mass;
                p += g.node[f][n].mass * g.node[f][n].momentum;
            }
            if (m <= 0) continue;
            const double w = st.weight(i, j);
            sum += w * (p / m);
            weight += w;
        }
    return weight > 0 ? Vec2(sum / weight) : Vec2::Zero();
}

// Velocity of the material on one side of the crack at x: each node's field is the one a
// particle just off the crack on that side would feed, weighted by w·m (as the contour
// transfer of eq. 25) so that a field holding only the tail of one particle's kernel, whose
// velocity is poorly determined, does not dominate where few nodes hold that side's
// material (a crack that curled on itself; unweighted, the PMMA drop tracked a face 75 m off
// its crack). Where no node holds that field the surface has nothing to follow and moves
// with the crack particle (`fallback`).
template <class Spline>
Vec2 surfaceVelocity(const SimulationState& s, const Vec2& side, const std::vector<int>& candidates,
                     const Vec2& fallback) {
    constexpr int W = Spline::width;
    const Grid& g = s.grid;
    const Stencil<Spline> st(side - g.origin, g.invDx);
    std::uint8_t fields[W * W];
    std::int32_t crossed[W * W];
    stencilFieldsOnGrid(s.segments, g, st, side, candidates, fields, crossed);
    Vec2 sum = Vec2::Zero();
    double weight = 0;
    for (int i = 0; i < W; ++i)
        for (int j = 0; j < W; ++j) {
            const int f = fields[i * W + j];
            const size_t n = g.index(st.baseX + i, st.baseY + j);
            const double wm = st.weight(i, j) * g.node[f][n].mass;
            if (wm <= 0) continue;
            sum += wm * g.node[f][n].momentum;
            weight += wm;
        }
    return weight > 0 ? Vec2(sum / weight) : fallback;
}

// The crack points move independently of each other (they read the grid, each writes only
// its own entries), so they are shared among the threads; the result does not depend on how.
template <class Spline>
void advect(SimulationState& s, double dt) {
    const double offset = 1e-4 * s.grid.dx; // "just off the crack"
    const double reach = (kernelRadius(s.scene.grid.kernel) + 0.01) * s.grid.dx;
    for (Crack& c : s.cracks) {
        std::vector<Vec2> moved(c.points.size());
        std::vector<int> candidates;
#pragma omp parallel for schedule(static) num_threads(s.threads) firstprivate(candidates)
        for (size_t k = 0; k < c.points.size(); ++k) {
            const Vec2 x = c.points[k];
            const Vec2 n = crackPointNormal(c, k);
            candidates.clear();
            s.segments.candidates(Box{x - Vec2::Constant(reach), x + Vec2::Constant(reach)}, candidates);
            const Vec2 centre = centreOfMassVelocity<Spline>(s.grid, x);
            // Surfaces are kept as offsets from the crack particle, which itself moves with the
            // centre-of-mass velocity; their difference is the crack opening (eqs. 23-24).
            c.above[k] += dt * (surfaceVelocity<Spline>(s, x + offset * n, candidates, centre) - centre);
            c.below[k] += dt * (surfaceVelocity<Spline>(s, x - offset * n, candidates, centre) - centre);
            moved[k] = x + dt * centre;
        }
        c.points = std::move(moved);
    }
}

} // namespace

void advectCracks(SimulationState& s, double dt) {
    if (s.scene.grid.kernel == KernelType::Cubic)
        advect<CubicSpline>(s, dt);
    else
        advect<QuadraticSpline>(s, dt);
}

} // namespace shatter::mpm
