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
    // Only the x86-64-v3 and -v4 copies use it, where floor is one rounding instruction (floorToInt
    // is for plain x86-64, whose floor is a library call); the same values.
    [[gnu::always_inline]] CubicRowStencil(const Vec2& local, double dx, double invDx) {
        const double fx = local.x() * invDx, fy = local.y() * invDx;
        const double ix = __builtin_floor(fx), iy = __builtin_floor(fy);
        baseX = int(ix) - 1;
        baseY = int(iy) - 1;
        axis(fx - ix, dx, invDx, wx, gx, ox);
        axis(fy - iy, dx, invDx, wy, gy, oy);
    }

    // The four nodes of one axis, for a particle at fraction t ∈ [0, 1) of a cell past the
    // second one. With s = 1 − t, u = (s, t, s, t):
    //   w = (s³/6, t³/2 − t² + 2/3, s³/2 − s² + 2/3, t³/6),
    //   dw/dt = (−s²/2, 3t²/2 − 2t, −3s²/2 + 2s, t²/2)   (CubicSpline::weightsAt).
    // Lanes 0 and 3 are plain products, so a weight at the edge of the support stays ≥ 0.
    // V is Double4, or Double8 for two particles (lanes 4-7: the second, whose t is in t's
    // lanes 4-7; CubicRowStencilPair), with the same operations per lane.
    template <class V, class T>
    [[gnu::always_inline]] static void axis(const T& t, double dx, double invDx, V& w, V& g, V& o) {
        const V u = repeat<V>(1, 0, 1, 0) + repeat<V>(-1, 1, -1, 1) * t;
        const V u2 = u * u, u3 = u2 * u;
        constexpr double sixth = 1.0 / 6.0, twoThirds = 2.0 / 3.0;
        w = u3 * repeat<V>(sixth, 0.5, 0.5, sixth) + (u2 * repeat<V>(0, -1, -1, 0) + repeat<V>(0, twoThirds, twoThirds, 0));
        g = (u2 * repeat<V>(-0.5, 1.5, -1.5, 0.5) + u * repeat<V>(0, -2, 2, 0)) * invDx;
        o = (repeat<V>(-1, 0, 1, 2) - t) * dx; // node k is k − 1 − t cells away
    }

private:
    // (a, b, c, d), once in a Double4, twice in a Double8.
    template <class V>
    [[gnu::always_inline]] static V repeat(double a, double b, double c, double d) {
        if constexpr (sizeof(V) == sizeof(Double4))
            return V{a, b, c, d};
        else
            return V{a, b, c, d, a, b, c, d};
    }
};

// The stencils of two particles, a and b, in Double8s: lanes 0-3 are a's CubicRowStencil,
// lanes 4-7 b's, the same values (the x86-64-v4 gather, GridToParticle.cpp).
struct CubicRowStencilPair {
    int baseXa = 0, baseYa = 0, baseXb = 0, baseYb = 0;
    Double8 wx, wy, gx, gy, ox, oy;

    [[gnu::always_inline]] CubicRowStencilPair(const Vec2& a, const Vec2& b, double dx, double invDx) {
        const double fxa = a.x() * invDx, fya = a.y() * invDx, fxb = b.x() * invDx, fyb = b.y() * invDx;
        const double ixa = __builtin_floor(fxa), iya = __builtin_floor(fya);
        const double ixb = __builtin_floor(fxb), iyb = __builtin_floor(fyb);
        baseXa = int(ixa) - 1;
        baseYa = int(iya) - 1;
        baseXb = int(ixb) - 1;
        baseYb = int(iyb) - 1;
        const double txa = fxa - ixa, tya = fya - iya, txb = fxb - ixb, tyb = fyb - iyb;
        CubicRowStencil::axis(Double8{txa, txa, txa, txa, txb, txb, txb, txb}, dx, invDx, wx, gx, ox);
        CubicRowStencil::axis(Double8{tya, tya, tya, tya, tyb, tyb, tyb, tyb}, dx, invDx, wy, gy, oy);
    }
};

} // namespace shatter::mpm
