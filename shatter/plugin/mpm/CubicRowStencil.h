#pragma once
// The cubic B-spline stencil of one particle with each axis in one Double4 (lane k: the
// stencil's k-th node along that axis): what the far-from-crack transfers of the cubic kernel
// need (ParticleToGrid.cpp, GridToParticle.cpp), a row of four nodes at a time.
// The values are those of Stencil<CubicSpline>: the same closed forms, evaluated per lane.
#include <shatter/plugin/mpm/BSpline.h>
#include <shatter/plugin/mpm/Double4.h>

namespace shatter::mpm {

struct CubicRowStencil {
    int baseX = 0, baseY = 0; // grid node of lane 0 on each axis
    Double4 wx, wy;           // 1D weights
    Double4 gx, gy;           // 1D weight slopes, per metre
    Double4 ox, oy;           // node position minus particle position, m

    // `local` is the particle's position relative to the grid origin, in metres.
    // Only the x86-64-v3 copies use it, where floor is one rounding instruction (floorToInt
    // is for plain x86-64, whose floor is a library call); the same values.
    [[gnu::always_inline]] CubicRowStencil(const Vec2& local, double dx, double invDx) {
        const double fx = local.x() * invDx, fy = local.y() * invDx;
        const double ix = __builtin_floor(fx), iy = __builtin_floor(fy);
        baseX = int(ix) - 1;
        baseY = int(iy) - 1;
        axis(fx - ix, dx, invDx, wx, gx, ox);
        axis(fy - iy, dx, invDx, wy, gy, oy);
    }

private:
    // The four nodes of one axis, for a particle at fraction t ∈ [0, 1) of a cell past the
    // second one. With s = 1 − t, u = (s, t, s, t):
    //   w = (s³/6, t³/2 − t² + 2/3, s³/2 − s² + 2/3, t³/6),
    //   dw/dt = (−s²/2, 3t²/2 − 2t, −3s²/2 + 2s, t²/2)   (CubicSpline::weightsAt).
    // Lanes 0 and 3 are plain products, so a weight at the edge of the support stays ≥ 0.
    [[gnu::always_inline]] static void axis(double t, double dx, double invDx, Double4& w, Double4& g, Double4& o) {
        const Double4 u = Double4{1, 0, 1, 0} + Double4{-1, 1, -1, 1} * t;
        const Double4 u2 = u * u, u3 = u2 * u;
        constexpr double sixth = 1.0 / 6.0, twoThirds = 2.0 / 3.0;
        w = u3 * Double4{sixth, 0.5, 0.5, sixth} + (u2 * Double4{0, -1, -1, 0} + Double4{0, twoThirds, twoThirds, 0});
        g = (u2 * Double4{-0.5, 1.5, -1.5, 0.5} + u * Double4{0, -2, 2, 0}) * invDx;
        o = (Double4{-1, 0, 1, 2} - t) * dx; // node k is k − 1 − t cells away
    }
};

} // namespace shatter::mpm
