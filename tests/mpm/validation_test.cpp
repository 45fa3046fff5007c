// The whole solver against fracture-mechanics handbook values, at the smallest resolution
// that meets the bounds (finer runs: shatter-mpm-validate --full).
#include <shatter/plugin/mpm/validation/CentreCrackedPlate.h>
#include <shatter/plugin/mpm/validation/InclinedCrack.h>

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace shatter::mpm {
namespace {

using namespace validation;

TEST(CentreCrackedPlate, TadaWithinFivePercentAtTenCellsPerHalfCrack) {
    // λ = 2a/W = 0.6 is the hardest of the three widths (F(λ) is steepest there). Both tips
    // see the same K_I (the plate is symmetric; 0.5% covers rounding of the seeding), and
    // there is no mode II (|K_II| < 2% K_I).
    CentreCrackedPlateCase c;
    c.lambda = 0.6;
    c.aOverDx = 10;
    const auto r = runCentreCrackedPlate(c);
    ASSERT_TRUE(r.valid);
    EXPECT_TRUE(r.converged);
    EXPECT_LT(r.error(), 0.05) << "K_I " << r.KIstart << " / " << r.KIend << " against " << r.KIreference;
    EXPECT_NEAR(r.KIstart, r.KIend, 5e-3 * r.KIreference);
    EXPECT_LT(std::abs(r.KIIstart), 0.02 * r.KIreference);
    EXPECT_LT(std::abs(r.KIIend), 0.02 * r.KIreference);
}

TEST(CentreCrackedPlate, ErrorFallsWithTheCellSize) {
    CentreCrackedPlateCase coarse, fine;
    coarse.lambda = fine.lambda = 0.6;
    coarse.aOverDx = 5;
    fine.aOverDx = 10;
    const auto rc = runCentreCrackedPlate(coarse), rf = runCentreCrackedPlate(fine);
    ASSERT_TRUE(rc.valid && rf.valid);
    EXPECT_LT(rf.error(), rc.error());
}

TEST(CentreCrackedPlate, TipsBetweenGridLinesActAtTheNearestNode) {
    // A discrete crack ends at a grid node (LineCrossing.h); it is rounded to the nearest
    // one. Tips 1/8 cell past a grid line (the plain line-crossing test: K_I +10.5%) and
    // 1/8 cell before the next: |Δa| = dx/8, which moves K_I by about 1.4% here (√a and
    // Tada's F(λ) at λ ≈ 0.6); 3% bounds that plus the 1% of the aligned case.
    for (double a : {10.125, 10.875}) {
        CentreCrackedPlateCase c;
        c.aOverDx = a;
        c.widthCells = 34; // centre on a grid line, tips a − 10 cells past one
        c.lambda = 2 * a / 34;
        const auto r = runCentreCrackedPlate(c);
        ASSERT_TRUE(r.valid);
        EXPECT_LT(r.error(), 0.03) << "a/dx " << a << ": K_I " << r.KIend << " against " << r.KIreference;
    }
}

TEST(InclinedCrack, KinksByTheHoopStressAngle) {
    // 45° crack, remote tension applied as the exact infinite-plate tractions on a square
    // plate: K_I = K_II = ½σ√(πa), kink −53.13°. Measured (start / end tip): a/dx = 4:
    // K_I −3.8/−1.6%, K_II +7.6/+8.7%; a/dx = 8: −0.9/0.0%, +3.4/+3.6%; a/dx = 16: −1.3/−3.0%,
    // +1.4/+1.5% (the tips sit differently in their cells at each size). So the 5%
    // bound holds from a/dx = 8. The first growth step kinks within 3° of −53.13° (measured
    // 0.5-0.7°), opposite in sign to K_II, at both tips.
    InclinedCrackCase c;
    const auto r = runInclinedCrack(c);
    ASSERT_TRUE(r.valid);
    for (int t = 0; t < 2; ++t) {
        EXPECT_NEAR(r.KI[t], r.KIreference, 0.05 * r.KIreference) << t;
        EXPECT_NEAR(r.KII[t], r.KIIreference, 0.05 * r.KIIreference) << t;
        EXPECT_NEAR(r.KII[t] / r.KI[t], 1.0, 0.05) << t;
        ASSERT_TRUE(r.grew[t]) << t;
        EXPECT_NEAR(r.kink[t] * 180 / std::numbers::pi, -53.13, 3.0) << t;
        EXPECT_LT(r.kink[t] * r.KII[t], 0) << t; // opposite sign
    }
}

} // namespace
} // namespace shatter::mpm
