// The J-integral routine on the exact Westergaard field, the reference field itself, and
// the hoop-stress formulas (corrected eqs. 33-34 of 001).
#include <shatter/plugin/mpm/HoopStress.h>
#include <shatter/plugin/mpm/WestergaardField.h>
#include <shatter/plugin/mpm/validation/ExactFieldCheck.h>

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace shatter::mpm {
namespace {

using validation::ExactFieldCase;
using validation::runExactFieldCase;

constexpr double kDegree = std::numbers::pi / 180;

TEST(WestergaardField, IsConsistentWithHookesLawAndItsOwnDisplacements) {
    WestergaardField f;
    f.a = 2;
    f.sigma = 1e6;
    f.tau = 4e5;
    f.E = 7e10;
    f.nu = 0.25;
    for (auto analysis : {Analysis::PlaneStress, Analysis::PlaneStrain}) {
        f.analysis = analysis;
        Material m;
        m.E = f.E;
        m.nu = f.nu;
        const double lambda = m.lameLambda(analysis), mu = m.shearModulus();
        for (const Vec2& p : {Vec2(2.3, 0.4), Vec2(-1.1, -0.7), Vec2(0.5, 1.9), Vec2(2.05, -0.02)}) {
            const auto s = f.at(p.x(), p.y());
            // Stress from the displacement gradient by Hooke's law: 1e-9 relative is rounding.
            const Mat2 eps = 0.5 * (s.gradU + s.gradU.transpose());
            const Mat2 hooke = lambda * eps.trace() * Mat2::Identity() + 2 * mu * eps;
            EXPECT_LT((hooke - s.stress).norm(), 1e-9 * s.stress.norm()) << p.transpose();
            // Gradient against central differences of u (h = 1e-6: truncation ~1e-11 relative).
            const double h = 1e-6;
            Mat2 fd;
            fd.col(0) = (f.at(p.x() + h, p.y()).u - f.at(p.x() - h, p.y()).u) / (2 * h);
            fd.col(1) = (f.at(p.x(), p.y() + h).u - f.at(p.x(), p.y() - h).u) / (2 * h);
            EXPECT_LT((fd - s.gradU).norm(), 1e-7 * s.gradU.norm()) << p.transpose();
        }
        // Far away the stress is the remote load.
        const auto far = f.at(1e5, 3e5);
        EXPECT_NEAR(far.stress(1, 1), f.sigma, 1e-6 * f.sigma);
        EXPECT_NEAR(far.stress(0, 1), f.tau, 1e-6 * f.sigma);
    }
}

// The bound: K_I and K_II within 0.5% of the exact values.
void expectWithinHalfPercent(const ExactFieldCase& c) {
    const auto r = runExactFieldCase(c);
    ASSERT_TRUE(r.valid);
    const double scale = std::hypot(r.KIref, r.KIIref);
    EXPECT_NEAR(r.KI, r.KIref, 5e-3 * scale) << "angle " << c.angle << " tip " << c.tip;
    EXPECT_NEAR(r.KII, r.KIIref, 5e-3 * scale) << "angle " << c.angle << " tip " << c.tip;
    EXPECT_NEAR(r.J, r.Jref, 1e-2 * r.Jref);
}

TEST(JIntegral, PureModeOneOnTheExactField) {
    ExactFieldCase c;
    c.a = 1.0;
    c.dx = 0.1;
    for (int tip : {0, 1}) {
        c.tip = tip;
        expectWithinHalfPercent(c);
    }
}

TEST(JIntegral, PureModeTwoOnTheExactField) {
    ExactFieldCase c;
    c.sigma = 0;
    c.tau = 1e6;
    for (int tip : {0, 1}) {
        c.tip = tip;
        expectWithinHalfPercent(c);
    }
}

TEST(JIntegral, MixedModeInclinedOffCentreCracksInBothAnalyses) {
    ExactFieldCase c;
    c.sigma = 1e6;
    c.tau = 6e5;
    c.centre = Vec2(3.7, -1.2);
    for (auto analysis : {Analysis::PlaneStress, Analysis::PlaneStrain})
        for (double angle : {30.0, 135.0, -100.0})
            for (int tip : {0, 1}) {
                c.analysis = analysis;
                c.angle = angle * kDegree;
                c.tip = tip;
                expectWithinHalfPercent(c);
            }
}

TEST(HoopStress, KinkAnglesOfTheCorrectedFormula) {
    // Erdogan & Sih: pure mode II kinks by ∓70.53° (opposite in sign to K_II); K_II = K_I
    // by −53.13°; pure mode I goes straight. Exact to rounding.
    EXPECT_NEAR(kinkAngle(0, 1), -70.528779 * kDegree, 1e-8);
    EXPECT_NEAR(kinkAngle(0, -1), 70.528779 * kDegree, 1e-8);
    EXPECT_NEAR(kinkAngle(1, 1), -53.130102 * kDegree, 1e-8);
    EXPECT_EQ(kinkAngle(1, 0), 0.0);
    // Against the tangent form θ = 2 atan((1 − √(1 + 8ρ²))/(4ρ)), ρ = K_II/K_I.
    for (double rho : {-3.0, -0.4, 0.01, 0.7, 5.0}) {
        const double tangentForm = 2 * std::atan((1 - std::sqrt(1 + 8 * rho * rho)) / (4 * rho));
        EXPECT_NEAR(kinkAngle(1, rho), tangentForm, 1e-12) << rho;
    }
}

TEST(HoopStress, CriterionIsTheHoopStressMaximumInTheKinkDirection) {
    // K_eff(θ) = K_I cos³(θ/2) − 3/2 K_II cos(θ/2) sin θ is √(2πr)·σ_θθ; it is largest at the
    // kink angle, and equals K_I in pure mode I.
    EXPECT_DOUBLE_EQ(effectiveStressIntensity(2.0, 0, 0), 2.0);
    for (double rho : {0.3, 1.0, -2.0}) {
        const double theta = kinkAngle(1, rho);
        const double best = effectiveStressIntensity(1, rho, theta);
        for (double d : {-0.01, 0.01}) EXPECT_LT(effectiveStressIntensity(1, rho, theta + d), best) << rho;
    }
    // Pure mode II: K_eff = (2/√3)... i.e. 1.1547·K_II at 70.5° (Erdogan & Sih).
    EXPECT_NEAR(effectiveStressIntensity(0, 1, kinkAngle(0, 1)), 2 / std::sqrt(3.0), 1e-12);
}

} // namespace
} // namespace shatter::mpm
