// A crack anywhere on the grid (issue 20): particles cut by an initial crack are split along
// it (CrackParticleSplit.h), so that each side holds exactly the material on its side of the
// line, and a symmetric crack off the grid lines shows no mode II.
#include <shatter/plugin/mpm/CrackParticleSplit.h>
#include <shatter/plugin/mpm/Solver2D.h>
#include <shatter/plugin/mpm/validation/CentreCrackedPlate.h>

#include "TestScenes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace shatter::mpm {
namespace {

constexpr double kRho = 1000;

// A 10 m × 10 m plate, 1 m cells, 2 particles per cell per axis (spacing 0.5 m), with a
// horizontal crack from x = 2 to 8 at height y.
Scene crackedPlate(double y) {
    Scene s = test::baseScene(1.0, test::elastic(ConstitutiveModelType::LinearElastic, 1e6, 0.3, kRho));
    s.bodies.push_back(Body{Shape(RectShape{Vec2(0, 0), Vec2(10, 10)}), 0, Vec2::Zero()});
    s.cracks.push_back(CrackSpec{{Vec2(2, y), Vec2(8, y)}, false, TipSelection::Both, {}});
    return s;
}

TEST(CrackParticleSplit, EachSideOfTheCrackHoldsTheMassOfItsSideOfTheLine) {
    // Columns x in [3, 7] (their squares lie between the crack's ends): below the line the
    // mass is ρ·4·y, whatever y is; without the split it was ρ·4·(the row boundary above y).
    for (double y : {5.0, 5.1, 5.25, 1.0 / 3 + 5, 5.4}) {
        const Solver2D solver(crackedPlate(y));
        const Particles& P = solver.particles();
        double below = 0, total = 0;
        for (size_t p = 0; p < P.size(); ++p) {
            total += P.mass[p];
            if (P.x0[p].x() > 3 && P.x0[p].x() < 7 && P.x0[p].y() < y) below += P.mass[p];
        }
        EXPECT_NEAR(total, kRho * 100, 1e-9 * kRho * 100) << y;
        // Parts under 5% of a particle (y = 5.0 lies on a row boundary, 5.4 leaves 0.1/0.5) are
        // not split off: the interface then moves by at most that share of the spacing.
        const double share = 0.05 * 0.5;
        EXPECT_NEAR(below, kRho * 4 * y, kRho * 4 * share + 1e-9) << y;
        if (y == 5.1 || y == 5.25) {
            EXPECT_NEAR(below, kRho * 4 * y, 1e-9 * kRho * 100) << y;
        }
    }
}

TEST(CrackParticleSplit, SquaresHoldingACrackEndAndSquaresTheCrackMissesStayWhole) {
    Particles particles;
    const double h = 0.5;
    for (const Vec2& x : {Vec2(2.25, 5.25), Vec2(4.25, 5.25), Vec2(4.25, 6.25), Vec2(7.75, 5.25)})
        particles.add(x, Vec2::Zero(), kRho * h * h, h * h, 0, 0);
    Crack crack;
    crack.points = {Vec2(2.3, 5.1), Vec2(5, 5.1), Vec2(7.6, 5.1)}; // ends inside the first and last squares
    EXPECT_EQ(splitParticlesAtCracks({crack}, h, particles), 1u);
    ASSERT_EQ(particles.size(), 5u);
    // The cut square [4, 4.5] × [5, 5.5]: 0.1 below the line, 0.4 above, centroids in the middle.
    EXPECT_NEAR(particles.mass[1], kRho * h * 0.1, 1e-9);
    EXPECT_NEAR(particles.x0[1].y(), 5.05, 1e-12);
    EXPECT_NEAR(particles.mass[4], kRho * h * 0.4, 1e-9);
    EXPECT_NEAR(particles.x0[4].y(), 5.3, 1e-12);
    EXPECT_NEAR(particles.x0[4].x(), 4.25, 1e-12);
    EXPECT_EQ(particles.x[4], particles.x0[4]);
}

// The centre-cracked plate at half its resolution (a/dx = 8, 2a/W = 0.5, plane
// strain, cubic kernel, 2 particles per cell per axis), its crack line `line` cells above a
// grid line.
validation::CentreCrackedPlateCase offGridPlate(double line) {
    validation::CentreCrackedPlateCase c;
    c.aOverDx = 8;
    c.widthCells = 32;
    c.lineOffset = line;
    c.analysis = Analysis::PlaneStrain;
    c.kernel = KernelType::Cubic;
    c.ppc = 2;
    return c;
}

TEST(CrackAnywhereOnTheGrid, ASymmetricCrackInTensionOffTheGridLinesHasNoModeTwo) {
    // The case at half its resolution (a/dx = 8, 2a/W = 0.5, plane strain, cubic
    // kernel, 2 particles per cell per axis), the crack line a quarter and a third of a cell
    // above a grid line: |K_II|/K_I < 1% at every wave transit after the load ramp. Before
    // the crack-end rounding looked at the node (LineCrossing.h) and cut particles were
    // split: 0.025-0.037 and creeping at a/dx = 16. The a/dx = 16 rows, with K_I within 2%,
    // are in shatter-mpm-validate --grid-offsets.
    for (double line : {0.25, 1.0 / 3}) {
        validation::CentreCrackedPlateCase c = offGridPlate(line);
        c.maxTransits = 4;
        const auto r = validation::runCentreCrackedPlate(c);
        ASSERT_TRUE(r.valid) << line;
        ASSERT_GE(r.mixityHistory.size(), 3u) << line;
        for (size_t k = 1; k < r.mixityHistory.size(); ++k) EXPECT_LT(r.mixityHistory[k], 0.01) << line << " " << k;
        EXPECT_NEAR(r.KIstart, r.KIend, 1e-3 * r.KIreference) << line;
        EXPECT_LT(r.error(), 0.03) << line << ": K_I " << r.KIend << " against " << r.KIreference;
    }
}

TEST(CrackAnywhereOnTheGrid, TipsInsideACellActWhereTheyAre) {
    // The plate above with its crack line a third of a cell above a grid line and the tips a
    // quarter and half a cell past one (2a/W = 0.5 kept): K_I within 3% of Tada's for the
    // true crack and no mode II. Rounded all or nothing, the tips 1/4 cell past a grid line
    // acted as if on it (LineCrossing.h): 1/4 cell short, about −2.8% of K_I at a/dx = 8 on
    // top of the solver's own error. The a/dx = 16 table (every line and tip offset, 2%) is
    // in shatter-mpm-validate --grid-offsets.
    for (double tip : {0.25, 0.5}) {
        validation::CentreCrackedPlateCase c = offGridPlate(1.0 / 3);
        c.aOverDx = 8 + tip;
        c.lambda = 2 * c.aOverDx / 32;
        c.maxTransits = 4;
        const auto r = validation::runCentreCrackedPlate(c);
        ASSERT_TRUE(r.valid) << tip;
        for (size_t k = 1; k < r.mixityHistory.size(); ++k) EXPECT_LT(r.mixityHistory[k], 0.01) << tip << " " << k;
        EXPECT_NEAR(r.KIstart, r.KIend, 1e-3 * r.KIreference) << tip;
        EXPECT_LT(r.error(), 0.03) << tip << ": K_I " << r.KIend << " against " << r.KIreference;
    }
}

TEST(CrackParticleSplit, AGrowthStepSplitsTheSquaresItCrossesAndKeepsMassAndMomentum) {
    // One square of side h = 0.5 around (4.25, 5.25), moving and stretched 1% along y: the
    // crack grows from inside it (4.2, 5.1 + stretch) to beyond it (4.7). The reference square
    // is cut 0.1 below the line as above; the parts keep F and the velocity, the positions
    // follow F, mass and momentum are kept. A second call splits nothing (parts are not
    // split again).
    const double h = 0.5;
    Particles particles;
    const Vec2 X(4.25, 5.25), v(0.3, -0.2);
    Mat2 F = Mat2::Identity();
    F(1, 1) = 1.01;
    particles.add(X, v, kRho * h * h, h * h, 0, 0);
    particles.Fe[0] = F;
    const Vec2 x = X + Vec2(1, 2); // moved
    particles.x[0] = x;
    const auto current = [&](const Vec2& ref) { return Vec2(x + F * (ref - X)); };
    Crack crack;
    crack.points = {current(Vec2(3.7, 5.1)), current(Vec2(4.2, 5.1)), current(Vec2(4.7, 5.1))};
    crack.above.assign(3, Vec2::Zero());
    crack.below.assign(3, Vec2::Zero());
    EXPECT_EQ(splitParticlesAtGrowth(crack, 1, h, particles), 1u);
    ASSERT_EQ(particles.size(), 2u);
    EXPECT_NEAR(particles.mass[0], kRho * h * 0.1, 1e-9);
    EXPECT_NEAR(particles.mass[1], kRho * h * 0.4, 1e-9);
    EXPECT_NEAR(particles.x0[0].y(), 5.05, 1e-12);
    EXPECT_NEAR(particles.x0[1].y(), 5.3, 1e-12);
    EXPECT_NEAR((particles.x[1] - current(Vec2(4.25, 5.3))).norm(), 0, 1e-12);
    EXPECT_NEAR((particles.x[0] - current(Vec2(4.25, 5.05))).norm(), 0, 1e-12);
    for (size_t p = 0; p < 2; ++p) {
        EXPECT_EQ(particles.v[p], v);
        EXPECT_EQ(particles.Fe[p], F);
    }
    EXPECT_EQ(splitParticlesAtGrowth(crack, 1, h, particles), 0u);
}

TEST(CrackAnywhereOnTheGrid, ARunningCrackOffTheGridLinesRunsStraight) {
    // The plate above (a/dx = 8, plane strain, cubic, 2 ppc), the crack line a third and a
    // quarter of a cell above a grid line, growing under a toughness just below the static
    // K_I: both tips take 8 steps, the path stays on the line to 2e-3 cells (a kink of
    // 0.01 rad would leave it within one step) and |K_II|/K_I at every analysis while it runs
    // stays below the 2% dead band (measured 1.4% and 0.9%; without the split at growth
    // 4.5% and 3.0%, and the path left the line). Before (issue 20) the running crack read
    // |K_II|/K_I 0.07-0.15 and kinked 0.1-0.2 rad within a few steps (K_II from the
    // antisymmetric part of J, √J_II, reads noise as mode II; and unsplit particles at the
    // new faces put the material interface on the lattice rows).
    for (double line : {0.25, 1.0 / 3}) {
        const validation::CentreCrackedPlateCase c = offGridPlate(line);
        Scene scene = validation::centreCrackedPlateScene(c);
        scene.cracks[0].propagate = true;
        scene.materials[0].Kc = 0.95 * validation::tadaCentreCrack(0.5) * c.sigma * std::sqrt(std::numbers::pi * 8);
        Solver2D solver(scene);
        const double y = scene.cracks[0].points[0].y();
        double worst = 0;
        const size_t initial = solver.cracks()[0].points.size();
        while (solver.cracks()[0].points.size() < initial + 16 && solver.time() < 4) {
            solver.step(1.0);
            if (solver.cracks()[0].points.size() == initial) continue; // not running yet
            for (const CrackTip& t : solver.cracks()[0].tips)
                if (t.result.KI > 0) worst = std::max(worst, std::abs(t.result.KII / t.result.KI));
        }
        const Crack& crack = solver.cracks()[0];
        EXPECT_GE(crack.points.size(), initial + 16) << line; // 8 steps at each tip
        EXPECT_LT(worst, 0.02) << line;
        for (const Vec2& p : crack.points) EXPECT_NEAR(p.y(), y, 2e-3) << line << ": " << p.transpose();
    }
}

} // namespace
} // namespace shatter::mpm
