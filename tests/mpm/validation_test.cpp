// The whole solver against fracture-mechanics handbook values, at the smallest resolution
// that meets the bounds (finer runs: shatter-mpm-validate --full).
#include "plugin/mpm/validation/CentreCrackedPlate.h"
#include "plugin/mpm/validation/InclinedCrack.h"

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

TEST(InclinedCrack, KinksByTheHoopStressAngle) {
    // 45° crack, uniaxial tension: K_I = K_II = ½σ√(πa) in an infinite plate, kink −53.13°.
    // Measured at a/dx = 8: K_I within 5% of the reference; K_II is the solver's known
    // weakness, too high by a first-order discretisation error (18% at a/dx = 8, 9.6% at
    // 16, 35% at 4, measured on the exact Westergaard boundary value problem), so it is
    // bounded here at 25% and tracked by shatter-mpm-validate. The first growth step still
    // kinks within 3° of −53.13°, opposite in sign to K_II, at both tips.
    InclinedCrackCase c;
    const auto r = runInclinedCrack(c);
    ASSERT_TRUE(r.valid);
    for (int t = 0; t < 2; ++t) {
        EXPECT_NEAR(r.KI[t], r.KIreference, 0.05 * r.KIreference) << t;
        EXPECT_NEAR(r.KII[t], r.KIIreference, 0.25 * r.KIIreference) << t;
        ASSERT_TRUE(r.grew[t]) << t;
        EXPECT_NEAR(r.kink[t] * 180 / std::numbers::pi, -53.13, 3.0) << t;
        EXPECT_LT(r.kink[t] * r.KII[t], 0) << t; // opposite sign
    }
}

} // namespace
} // namespace shatter::mpm
