// The shrink interval (LatticeSettings::shrinkInterval): the anchored piece's body shrinks at
// most once per interval, every break decided meanwhile comes apart at the next shrink with mass
// and momentum carried as in any split, the same seed gives the same bits, and 1 is every step.
#include <shatter/bullet_ext/lattice/LatticeBody.h>
#include <shatter/bullet_ext/lattice/LatticeSystem.h>
#include <shatter/bullet_ext/Plugin.h>
#include <shatter/bullet_ext/VisualBody.h>
#include <shatter/plugin/common/InputError.h>
#include <shatter/plugin/lattice/Fragments.h>
#include "tests/bullet_ext/lattice/WallScene.h"
#include "tests/support/PartsConserve.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

namespace shatter {
namespace {

using test::WallScene;

// A 200 kg ball at 8 m/s: the wall breaks in many consecutive steps.
struct Hit : WallScene {
    explicit Hit(int interval, std::uint64_t seed = 1) : WallScene(8.0, seed, 200.0, {}, 0, interval) {}
};

// The anchored piece's body: the one body every shrink keeps.
const VisualBody* anchoredBody(const LatticeBody& wall) {
    for (const auto& p : wall.pieces())
        if (p.lattice.anchored) return p.body;
    return nullptr;
}

// Steps (from 1) in which the anchored piece's body shrank, over `steps` steps; every split
// conserves mass (and momentum, if it moved).
std::vector<int> shrinkSteps(Hit& s, int steps) {
    std::vector<int> shrank;
    const VisualBody* anchored = anchoredBody(*s.wall);
    for (int step = 1; step <= steps; ++step) {
        s.w.step(1);
        for (const auto& record : s.plugin.lattices().takeSplitRecords()) {
            if (record.parent.linearMomentum().norm() > 0.0) { // a static parent carries no momentum to compare
                test::expectPartsConserveTheWhole(record.parent, record.parts);
            } else {
                double mass = 0.0;
                for (const auto& part : record.parts) mass += part.mass;
                EXPECT_NEAR(mass, record.parent.mass, 1e-12 * record.parent.mass) << "step " << step;
            }
            if (std::count(record.bodies.begin(), record.bodies.end(), anchored) > 0) shrank.push_back(step);
        }
        EXPECT_NEAR(s.wall->currentMass(), s.wall->initialMass(), 1e-9 * s.wall->initialMass()) << "step " << step;
    }
    return shrank;
}

int shortestGap(const std::vector<int>& steps) {
    int gap = 1 << 30;
    for (size_t i = 1; i < steps.size(); ++i) gap = std::min(gap, steps[i] - steps[i - 1]);
    return gap;
}

TEST(LatticeShrinkInterval, TheAnchoredBodyShrinksAtMostOncePerIntervalAndEveryBreakComesApart) {
    Hit everyStep(1);
    const std::vector<int> control = shrinkSteps(everyStep, 60);
    ASSERT_GE(control.size(), 3u);
    ASSERT_EQ(shortestGap(control), 1) << "the control must shrink in consecutive steps";
    Hit s(4);
    const std::vector<int> shrank = shrinkSteps(s, 60);
    ASSERT_GE(shrank.size(), 3u);
    EXPECT_GE(shortestGap(shrank), 4);
    // What waits comes apart at a later shrink: within a few more steps nothing waits, and every
    // piece is one connected part.
    auto waiting = [&] {
        return std::any_of(s.wall->pieces().begin(), s.wall->pieces().end(), [](const auto& p) { return p.splitPending; });
    };
    for (int step = 0; step < 40 && waiting(); ++step) s.w.step(1);
    EXPECT_FALSE(waiting());
    for (const auto& p : s.wall->pieces())
        EXPECT_EQ(lattice::connectedComponents(s.wall->lattice(), p.lattice.particles).size(), 1u);
}

TEST(LatticeShrinkInterval, SameSeedGivesTheSameBits) {
    Hit a(4, 3), b(4, 3);
    a.w.step(80);
    b.w.step(80);
    ASSERT_EQ(a.wall->pieceCount(), b.wall->pieceCount());
    ASSERT_GT(a.wall->pieceCount(), 5);
    for (int i = 0; i < a.wall->pieceCount(); ++i) {
        const auto& pa = a.wall->pieces()[i];
        const auto& pb = b.wall->pieces()[i];
        EXPECT_EQ(pa.lattice.particles, pb.lattice.particles);
        const btTransform& ta = pa.body->rigidBody().getWorldTransform();
        const btTransform& tb = pb.body->rigidBody().getWorldTransform();
        EXPECT_TRUE(ta.getOrigin() == tb.getOrigin() && ta.getBasis() == tb.getBasis()) << "piece " << i;
        EXPECT_TRUE(pa.body->rigidBody().getLinearVelocity() == pb.body->rigidBody().getLinearVelocity()) << "piece " << i;
    }
}

TEST(LatticeShrinkInterval, AnIntervalOfZeroIsAnErrorNamingTheBody) {
    try {
        Hit s(0);
        FAIL() << "no error";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("wall"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("shrink interval"), std::string::npos) << e.what();
    }
}

} // namespace
} // namespace shatter
