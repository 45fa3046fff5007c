// The weighting functions' reproducing properties, which the transfers' conservation rests on.
#include <shatter/plugin/mpm/BSpline.h>

#include <gtest/gtest.h>

#include <random>

namespace shatter::mpm {
namespace {

// Rounding of sums of 16 terms of order 1: 1e-13 is ~500 ulp, far below any modelling error.
constexpr double kTol = 1e-13;

template <class Spline>
void checkReproduction(double apicD) {
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(3.0, 9.0);
    const double dx = 0.37;
    for (int trial = 0; trial < 200; ++trial) {
        const Vec2 x(u(rng) * dx, u(rng) * dx);
        const Stencil<Spline> st(x, 1 / dx);
        double sum = 0;
        Vec2 first = Vec2::Zero(), gradSum = Vec2::Zero();
        Mat2 second = Mat2::Zero(), gradX = Mat2::Zero();
        for (int i = 0; i < Spline::width; ++i)
            for (int j = 0; j < Spline::width; ++j) {
                const Vec2 d = dx * Vec2(st.baseX + i, st.baseY + j) - x;
                const double w = st.weight(i, j);
                sum += w;
                first += w * d;
                second += w * d * d.transpose();
                gradSum += st.gradient(i, j);
                gradX += d * st.gradient(i, j).transpose();
            }
        EXPECT_NEAR(sum, 1, kTol);                       // partition of unity: mass is conserved
        EXPECT_NEAR(first.norm(), 0, kTol * dx);         // linear reproduction: momentum
        EXPECT_NEAR((second / (dx * dx) - Mat2::Identity() / apicD).norm(), 0, kTol); // APIC's D
        EXPECT_NEAR(gradSum.norm(), 0, kTol / dx);       // a uniform field has no gradient
        EXPECT_NEAR((gradX - Mat2::Identity()).norm(), 0, kTol); // a linear field has its own
    }
}

TEST(BSpline, CubicReproducesLinearFieldsAndApicInertia) { checkReproduction<CubicSpline>(3.0); }
TEST(BSpline, QuadraticReproducesLinearFieldsAndApicInertia) { checkReproduction<QuadraticSpline>(4.0); }

TEST(BSpline, SlopeIsTheDerivativeOfTheValue) {
    // Central differences with h = 1e-6 are exact to O(h²) ~ 1e-12 on these piecewise cubics,
    // plus rounding ~1e-10; points avoid the knots where the second derivative jumps.
    for (double x = -2.45; x < 2.5; x += 0.1) {
        const double h = 1e-6;
        EXPECT_NEAR(CubicSpline::slope(x), (CubicSpline::value(x + h) - CubicSpline::value(x - h)) / (2 * h), 1e-8);
        EXPECT_NEAR(QuadraticSpline::slope(x), (QuadraticSpline::value(x + h) - QuadraticSpline::value(x - h)) / (2 * h),
                    1e-8);
    }
}

} // namespace
} // namespace shatter::mpm
