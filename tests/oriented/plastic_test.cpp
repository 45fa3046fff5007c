// Plastic deformation of a rigid-between-impacts body (source 000 §3.5).
#include "OrientedFixtures.h"
#include <shatter/plugin/common/InputError.h>
#include <shatter/plugin/oriented/PlasticDeformation.h>

#include <gtest/gtest.h>

namespace shatter::oriented {
namespace {

// A 12 × 12 plate of 5 cm × 5 cm × 1 cm tiles: a door in miniature.
test::CubeBlock plate() {
    test::CubeBlock b = test::cubeBlock(12, 12, 1, 0.05);
    return b;
}

Dent pushDown(int particle, double depth) { return {particle, Eigen::Vector3d(0, 0, -depth)}; }

TEST(PlasticDeformation, NoDentLeavesTheBodyUnchanged) {
    auto solver = test::blockSolver(plate());
    const auto before = solver.particles();
    const PlasticResult r = deformPlastically(solver, {}, {});
    EXPECT_TRUE(r.moved.empty());
    EXPECT_EQ(r.maxDisplacement, 0.0);
    for (int i = 0; i < before.size(); ++i) EXPECT_EQ(solver.particles().restPosition[i], before.restPosition[i]);
}

TEST(PlasticDeformation, DentIsLocalSmoothAndBecomesTheRestShape) {
    auto solver = test::blockSolver(plate());
    const int hit = 6 * 12 + 6;
    const Dent dent = pushDown(hit, 0.02);
    const auto restBefore = solver.particles().restPosition;
    const PlasticResult r = deformPlastically(solver, std::span(&dent, 1), {});
    const auto& p = solver.particles();
    EXPECT_NEAR(r.maxDisplacement, 0.02, 1e-12);
    EXPECT_NEAR(p.restPosition[hit].z() - restBefore[hit].z(), -0.02, 1e-12);
    // Neighbours follow part of the way, less further out; three rings out nothing moves.
    const double near = restBefore[hit + 1].z() - p.restPosition[hit + 1].z();
    const double far = restBefore[hit + 2].z() - p.restPosition[hit + 2].z();
    EXPECT_GT(near, 0.002);
    EXPECT_LT(near, 0.02);
    EXPECT_GT(far, 0.0);
    EXPECT_LT(far, near);
    EXPECT_EQ(p.restPosition[hit + 3], restBefore[hit + 3]);
    EXPECT_EQ(p.restPosition[0], restBefore[0]);
    // The new rest pose is the current pose: the body is at rest again, nothing to correct.
    for (int i = 0; i < p.size(); ++i) {
        EXPECT_EQ(p.position[i], p.restPosition[i]);
        EXPECT_TRUE(p.orientation[i].coeffs().isApprox(Eigen::Quaterniond::Identity().coeffs()));
        EXPECT_LT((solver.deformation(i) - Eigen::Matrix3d::Identity()).norm(), 1e-9);
    }
}

TEST(PlasticDeformation, DeeperOffsetGivesADeeperDent) {
    double last = 0.0;
    for (double depth : {0.005, 0.01, 0.02}) {
        auto solver = test::blockSolver(plate());
        const Dent dent = pushDown(66, depth);
        const double moved = deformPlastically(solver, std::span(&dent, 1), {}).maxDisplacement;
        EXPECT_GT(moved, last);
        last = moved;
    }
}

TEST(PlasticDeformation, JointFixedPrimitivesDoNotMove) {
    auto solver = test::blockSolver(plate());
    auto& p = solver.particles();
    for (int i = 0; i < 12; ++i) p.fixed[i * 12 + 5] = true; // a fixed column through the dent
    const auto before = p.restPosition;
    const Dent dents[] = {pushDown(6 * 12 + 5, 0.02), pushDown(6 * 12 + 6, 0.02)};
    const PlasticResult r = deformPlastically(solver, dents, {});
    for (int i = 0; i < 12; ++i) EXPECT_EQ(p.restPosition[i * 12 + 5], before[i * 12 + 5]) << i;
    EXPECT_NEAR(r.maxDisplacement, 0.02, 1e-12); // the free hit tile still dents
    for (int i = 0; i < 12; ++i) EXPECT_TRUE(p.fixed[i * 12 + 5]); // flags are restored
}

TEST(PlasticDeformation, BadDentsAndSettingsAreErrorsNamingTheObject) {
    auto solver = test::blockSolver(plate());
    const Dent unknown = pushDown(1000, 0.01);
    EXPECT_THROW(deformPlastically(solver, std::span(&unknown, 1), {}), InputError);
    const Dent nan{3, Eigen::Vector3d(0, 0, std::nan(""))};
    EXPECT_THROW(deformPlastically(solver, std::span(&nan, 1), {}), InputError);
    PlasticSettings bad;
    bad.rings = 0;
    try {
        deformPlastically(solver, {}, bad);
        FAIL();
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("body 'block': plastic rings"), std::string::npos) << e.what();
    }
}

} // namespace
} // namespace shatter::oriented
