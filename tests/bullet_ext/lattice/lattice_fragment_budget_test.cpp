// The fragment budget (LatticeSettings::fragmentBudget): no step makes more new bodies than it,
// the parts left for later come apart in the next steps with mass and momentum carried as in
// any split, and the same seed gives the same bits.
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

namespace shatter {
namespace {

using test::WallScene;

// A 200 kg ball at 8 m/s: 160-odd fragments within a second, 40-odd of them in one step.
struct BudgetHit : WallScene {
    explicit BudgetHit(int budget, std::uint64_t seed = 1) : WallScene(8.0, seed, 200.0, {}, budget) {}
};

// The most new bodies any step made over 160 steps, and the fragments at the end.
struct Made {
    int mostInAStep = 0, pieces = 0;
};
Made run(BudgetHit& s) {
    Made r;
    for (int step = 0; step < 160; ++step) {
        const int before = s.plugin.lattices().timing().fragmentsCreated;
        s.w.step(1);
        r.mostInAStep = std::max(r.mostInAStep, s.plugin.lattices().timing().fragmentsCreated - before);
    }
    r.pieces = s.wall->pieceCount();
    return r;
}

TEST(LatticeFragmentBudget, NoStepMakesMoreBodiesThanTheBudgetAndEveryPartComesApart) {
    BudgetHit unlimited(0);
    const Made control = run(unlimited);
    ASSERT_GT(control.mostInAStep, 8) << "the control must make more than the budget in a step";
    BudgetHit s(4);
    const Made r = run(s);
    EXPECT_LE(r.mostInAStep, 4);
    EXPECT_GT(r.pieces, 40);
    // Nothing is left waiting, and every piece is one connected part.
    for (const auto& p : s.wall->pieces()) {
        EXPECT_FALSE(p.splitPending);
        EXPECT_EQ(lattice::connectedComponents(s.wall->lattice(), p.lattice.particles).size(), 1u);
    }
    EXPECT_NEAR(s.wall->currentMass(), s.wall->initialMass(), 1e-9 * s.wall->initialMass());
}

TEST(LatticeFragmentBudget, PartsLeftForLaterCarryMassAndMomentumAsAnySplit) {
    BudgetHit s(4);
    int splits = 0, held = 0;
    for (int step = 0; step < 160; ++step) {
        s.w.step(1);
        for (const auto& p : s.wall->pieces()) held += p.splitPending;
        for (const auto& record : s.plugin.lattices().takeSplitRecords()) {
            if (record.parent.linearMomentum().norm() > 0.0) { // a static parent carries no momentum to compare
                test::expectPartsConserveTheWhole(record.parent, record.parts);
                ++splits;
            }
        }
        EXPECT_NEAR(s.wall->currentMass(), s.wall->initialMass(), 1e-9 * s.wall->initialMass()) << "step " << step;
    }
    EXPECT_GT(splits, 10) << "splits of moving pieces";
    EXPECT_GT(held, 0) << "no part was ever left for later: the budget was not exercised";
}

TEST(LatticeFragmentBudget, SameSeedGivesTheSameBits) {
    BudgetHit a(4, 3), b(4, 3);
    a.w.step(80);
    b.w.step(80);
    ASSERT_EQ(a.wall->pieceCount(), b.wall->pieceCount());
    for (int i = 0; i < a.wall->pieceCount(); ++i) {
        const auto& pa = a.wall->pieces()[i];
        const auto& pb = b.wall->pieces()[i];
        EXPECT_EQ(pa.lattice.particles, pb.lattice.particles);
        EXPECT_EQ(pa.splitPending, pb.splitPending);
        const btTransform& ta = pa.body->rigidBody().getWorldTransform();
        const btTransform& tb = pb.body->rigidBody().getWorldTransform();
        EXPECT_TRUE(ta.getOrigin() == tb.getOrigin() && ta.getBasis() == tb.getBasis()) << "piece " << i;
        const btVector3 va = pa.body->rigidBody().getLinearVelocity(), vb = pb.body->rigidBody().getLinearVelocity();
        EXPECT_TRUE(va == vb) << "piece " << i;
    }
}

TEST(LatticeFragmentBudget, ABudgetOfOneIsAnErrorNamingTheBody) {
    try {
        BudgetHit s(1);
        FAIL() << "no error";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("wall"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("fragment budget"), std::string::npos) << e.what();
    }
}

} // namespace
} // namespace shatter
