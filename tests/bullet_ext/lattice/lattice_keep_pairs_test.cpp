// LatticeSettings::keepPairsOnShrink: the part of a split that keeps the piece's body loses the
// other parts' primitives with the body left in the world, its pairs kept. Splits carry mass and
// momentum as ever, and the wall's anchored part keeps its pair with the ground.
#include <shatter/bullet_ext/lattice/LatticeBody.h>
#include <shatter/bullet_ext/lattice/LatticeSystem.h>
#include <shatter/bullet_ext/Plugin.h>
#include <shatter/bullet_ext/VisualBody.h>
#include "tests/bullet_ext/lattice/WallScene.h"
#include "tests/support/PartsConserve.h"

#include <gtest/gtest.h>

#include <map>

namespace shatter {
namespace {

using test::WallScene;

// A 200 kg ball at 8 m/s into the anchored wall: 160-odd fragments within a second. With a
// fragment budget, loose pieces hold parts for later and lose them in the next steps: their
// bodies shrink too, moving.
struct PairsHit : WallScene {
    explicit PairsHit(bool keepPairs, int budget = 0) : WallScene(8.0, 1, 200.0, {}, budget, keepPairs) {}
};

// Contact points of the body's manifolds.
int pointsOf(PairsHit& s, const btCollisionObject& body) {
    int points = 0;
    btDispatcher& d = *s.w.world.getDispatcher();
    for (int m = 0; m < d.getNumManifolds(); ++m) {
        const btPersistentManifold* manifold = d.getManifoldByIndexInternal(m);
        if (manifold->getBody0() == &body || manifold->getBody1() == &body) points += manifold->getNumContacts();
    }
    return points;
}

TEST(LatticeKeepPairs, SplitsCarryMassAndMomentumWithThePairsKept) {
    PairsHit s(true, 4);
    int splits = 0, staticShrinks = 0;
    for (int step = 0; step < 160; ++step) {
        std::map<const VisualBody*, std::size_t> still; // tets of the static pieces before the step
        for (const auto& p : s.wall->pieces())
            if (p.body->rigidBody().getInvMass() == 0) still[p.body] = p.lattice.particles.size();
        s.w.step(1);
        for (const auto& p : s.wall->pieces()) {
            const auto it = still.find(p.body);
            staticShrinks += it != still.end() && p.lattice.particles.size() < it->second;
        }
        for (const auto& record : s.plugin.lattices().takeSplitRecords()) {
            if (record.parent.linearMomentum().norm() > 0.0) { // a static parent carries no momentum to compare
                test::expectPartsConserveTheWhole(record.parent, record.parts);
                ++splits;
            }
        }
        EXPECT_NEAR(s.wall->currentMass(), s.wall->initialMass(), 1e-9 * s.wall->initialMass()) << "step " << step;
    }
    EXPECT_GT(splits, 3) << "splits of moving pieces";
    EXPECT_GT(s.wall->pieceCount(), 20);
    // Moving pieces lost parts in the world too (their frames moved to their new centres); a
    // loose piece's first shrink leaves the world (it then collides as its group framed anew).
    EXPECT_GT(staticShrinks, 0);
    EXPECT_GT(s.plugin.lattices().timing().shrinksInWorld, staticShrinks);
}

TEST(LatticeKeepPairs, TheAnchoredPartKeepsItsContactsAcrossItsShrinks) {
    for (const bool keep : {true, false}) {
        PairsHit s(keep);
        const VisualBody* body = s.wall->pieces().front().body; // anchored: its part that stays keeps it
        const btRigidBody& wall = body->rigidBody();
        const auto tetsOfWall = [&] {
            for (const auto& p : s.wall->pieces())
                if (p.body == body) return p.lattice.particles.size();
            return std::size_t(0);
        };
        int shrinks = 0, pointsKept = 0;
        std::size_t tets = tetsOfWall();
        for (int step = 0; step < 60; ++step) {
            s.w.step(1);
            const std::size_t now = tetsOfWall();
            ASSERT_GT(now, 0u);
            if (now == tets) continue;
            tets = now;
            ++shrinks;
            // Out of the world, the body's manifolds go with the shrink; they are made anew at the next step.
            pointsKept += pointsOf(s, wall);
        }
        ASSERT_GT(shrinks, 0) << "the anchored part must lose parts";
        if (keep) EXPECT_GT(pointsKept, 0);
        else EXPECT_EQ(pointsKept, 0);
    }
}

} // namespace
} // namespace shatter
