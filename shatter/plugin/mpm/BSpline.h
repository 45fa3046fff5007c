#pragma once
// B-spline weighting functions between particles and grid nodes. The cubic spline is the
// source's choice (support of 4 nodes per axis); the quadratic one (3 nodes) is cheaper.
// Weights are tensor products N(x)N(y) of the 1D spline evaluated at (x_p - x_i)/dx.
#include <shatter/plugin/mpm/Types.h>

#include <cmath>

namespace shatter::mpm {

enum class KernelType { Cubic, Quadratic };

// Nodes per axis that a particle touches.
constexpr int kernelWidth(KernelType k) { return k == KernelType::Cubic ? 4 : 3; }

// Radius of the support in cells (the weight is zero beyond it).
constexpr double kernelRadius(KernelType k) { return k == KernelType::Cubic ? 2.0 : 1.5; }

// 1/D of APIC (Jiang et al. 2015): D = dx²/3 for the cubic spline, dx²/4 for the quadratic.
constexpr double apicInverseInertia(KernelType k) { return k == KernelType::Cubic ? 3.0 : 4.0; }

// floor() without the libm call that plain SSE2 code needs for std::floor.
inline int floorToInt(double f) {
    const int i = int(f);
    return f < i ? i - 1 : i;
}

struct CubicSpline {
    static constexpr int width = 4;
    static double value(double x) {
        const double a = std::abs(x);
        if (a < 1) return 0.5 * a * a * a - a * a + 2.0 / 3.0;
        if (a < 2) return (2 - a) * (2 - a) * (2 - a) / 6.0;
        return 0;
    }
    static double slope(double x) {
        const double a = std::abs(x);
        if (a < 1) return 1.5 * x * a - 2 * x;
        if (a < 2) return -0.5 * (2 - a) * (2 - a) * (x > 0 ? 1 : -1);
        return 0;
    }
    // The first node index with a non-zero weight for position f (in cells), and the four
    // weights and slopes (per cell) there, in closed form: the same values
    // as value()/slope() at offsets 1 + t, t, t − 1, t − 2, without their branches.
    // The first node index alone (what stencil() returns).
    static int first(double f) { return floorToInt(f) - 1; }
    static int stencil(double f, double w[4], double g[4]) {
        const int i = floorToInt(f);
        weightsAt(f - i, w, g);
        return i - 1;
    }
    // stencil() for both axes at once: the same operations in the same order (so the same
    // bits), on packed pairs (x, y), which halves the arithmetic of the hottest loops.
    static Eigen::Array2i first2(const Eigen::Array2d& f) {
        return Eigen::Array2i(floorToInt(f.x()), floorToInt(f.y())) - 1;
    }
    static void stencil2(const Eigen::Array2d& f, const Eigen::Array2i& base, Eigen::Array2d w[4],
                         Eigen::Array2d g[4]) {
        weightsAt<Eigen::Array2d>(f - (base + 1).cast<double>(), w, g);
    }

private:
    // Weights and slopes at fraction t past the stencil's second node; T is double or a pair.
    template <class T>
    static void weightsAt(const T& t, T w[4], T g[4]) {
        const T s = 1 - t;
        const T t2 = t * t, t3 = t2 * t, s2 = s * s;
        constexpr double sixth = 1.0 / 6.0;
        w[0] = s2 * s * sixth;
        w[1] = 0.5 * t3 - t2 + 2.0 / 3.0;
        w[2] = 0.5 * s2 * s - s2 + 2.0 / 3.0;
        w[3] = t3 * sixth;
        g[0] = -0.5 * s2;
        g[1] = 1.5 * t2 - 2 * t;
        g[2] = -1.5 * s2 + 2 * s;
        g[3] = 0.5 * t2;
    }
};

struct QuadraticSpline {
    static constexpr int width = 3;
    static double value(double x) {
        const double a = std::abs(x);
        if (a < 0.5) return 0.75 - a * a;
        if (a < 1.5) return 0.5 * (1.5 - a) * (1.5 - a);
        return 0;
    }
    static double slope(double x) {
        const double a = std::abs(x);
        if (a < 0.5) return -2 * x;
        if (a < 1.5) return -(1.5 - a) * (x > 0 ? 1 : -1);
        return 0;
    }
    // The first node index for position f (in cells) and the three weights and slopes, in
    // closed form; u = f − first node ∈ [0.5, 1.5).
    static int first(double f) { return floorToInt(f - 0.5); }
    static int stencil(double f, double w[3], double g[3]) {
        const int i = floorToInt(f - 0.5);
        weightsAt(f - i, w, g);
        return i;
    }
    static Eigen::Array2i first2(const Eigen::Array2d& f) {
        return Eigen::Array2i(floorToInt(f.x() - 0.5), floorToInt(f.y() - 0.5));
    }
    static void stencil2(const Eigen::Array2d& f, const Eigen::Array2i& base, Eigen::Array2d w[3],
                         Eigen::Array2d g[3]) {
        weightsAt<Eigen::Array2d>(f - base.cast<double>(), w, g);
    }

private:
    // Weights and slopes at u = f − first node; T is double or a pair.
    template <class T>
    static void weightsAt(const T& u, T w[3], T g[3]) {
        const T a = 1.5 - u, b = u - 1, c = u - 0.5;
        w[0] = 0.5 * a * a;
        w[1] = 0.75 - b * b;
        w[2] = 0.5 * c * c;
        g[0] = -a;
        g[1] = -2 * b;
        g[2] = c;
    }
};

// Weights and weight gradients of one point against the W x W nodes around it.
// Node (i, j) of the stencil is grid node (baseX + i, baseY + j).
template <class Spline>
struct Stencil {
    static constexpr int width = Spline::width;
    int baseX = 0, baseY = 0;
    double wx[width], wy[width];   // 1D weights
    double gx[width], gy[width];   // 1D weight slopes, already divided by dx

    // `local` is the position relative to the grid origin, in metres.
    Stencil(const Vec2& local, double invDx) {
        const Eigen::Array2d f = local.array() * invDx;
        const Eigen::Array2i base = Spline::first2(f);
        Eigen::Array2d w[width], g[width];
        Spline::stencil2(f, base, w, g);
        baseX = base.x();
        baseY = base.y();
        for (int k = 0; k < width; ++k) {
            g[k] *= invDx;
            wx[k] = w[k].x();
            wy[k] = w[k].y();
            gx[k] = g[k].x();
            gy[k] = g[k].y();
        }
    }
    double weight(int i, int j) const { return wx[i] * wy[j]; }
    Vec2 gradient(int i, int j) const { return Vec2(gx[i] * wy[j], wx[i] * gy[j]); }
};

// The weight of a point at offset d (metres) from another, for transfers that do not go
// through the grid (particles to J-integral contour points).
template <class Spline>
double pointWeight(const Vec2& d, double invDx) {
    return Spline::value(d.x() * invDx) * Spline::value(d.y() * invDx);
}

} // namespace shatter::mpm
