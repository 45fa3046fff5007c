// A real shape (issue 19): Spot, tetrahedralized by TetGen without a quality bound (the shipped
// demos/assets/spot_tets.ele: 2,281 tets, 58 slivers), anchored by its hooves (a region in
// world coordinates) and hit by a ball, and dropped free and hit. No fragment moves faster
// than the contact speed limit allows (LatticeSettings::hitSpeedFactor times the speed of what
// hit it, plus what gravity adds), energy does not grow, mass is kept to 1e-9 and every split
// of a moving piece hands on its momenta (tests/support/PartsConserve.h). (That no sliver
// breaks off alone is tested on the lattice: tests/lattice/slivers_test.cpp. In these two
// scenes none did even unbound.)
#include <shatter/bullet_ext/Plugin.h>
#include <shatter/bullet_ext/VisualBody.h>
#include <shatter/bullet_ext/lattice/LatticeBody.h>
#include <shatter/bullet_ext/lattice/LatticeSystem.h>
#include <shatter/plugin/lattice/AnchorRegion.h>
#include <shatter/plugin/lattice/TetGenReader.h>
#include "tests/support/PartsConserve.h"
#include "tests/support/TestWorld.h"

#include <gtest/gtest.h>

#include <memory>

namespace shatter {
namespace {

lattice::TetMesh spotMesh() { return lattice::readTetGen(std::string(SHATTER_SOURCE_DIR) + "/demos/assets/spot_tets.ele"); }

// Spot standing on the ground (its lowest node at y = 0) and a 0.12 m ball flying at its flank.
struct SpotScene {
    static constexpr btScalar kBallMass = 80;
    test::TestWorld w;
    Plugin plugin{w.world};
    LatticeBody* spot = nullptr;
    btSphereShape ballShape{0.12f};
    std::unique_ptr<btRigidBody> ball;
    double ballSpeed;

    SpotScene(double speed, bool anchored, bool replay, double lift = 0.0) : ballSpeed(speed) {
        w.addGround();
        w.world.getSolverInfo().m_splitImpulse = 1;
        w.world.getSolverInfo().m_splitImpulsePenetrationThreshold = 0;
        const lattice::TetMesh mesh = spotMesh();
        LatticeSettings s;
        s.name = "spot";
        s.replayImpacts = replay;
        // Its hooves: the tets whose centroid is within 5 cm of the ground where it stands.
        if (anchored) s.anchorRegions = {lattice::AnchorRegion::below(0.05).inWorld()};
        double lowest = INFINITY;
        for (const auto& n : mesh.nodes) lowest = std::min(lowest, n.y());
        spot = &plugin.addLatticeBody(mesh, s, btTransform(btQuaternion::getIdentity(), btVector3(0, btScalar(lift - lowest), 0)));
        btVector3 inertia;
        ballShape.calculateLocalInertia(kBallMass, inertia);
        ball = std::make_unique<btRigidBody>(kBallMass, nullptr, &ballShape, inertia);
        ball->setWorldTransform(btTransform(btQuaternion::getIdentity(), btVector3(0.7f, btScalar(lift + 0.8), 0.4f)));
        ball->setLinearVelocity(btVector3(btScalar(-speed), 0, 0));
        w.world.addRigidBody(ball.get());
    }
    ~SpotScene() { w.world.removeRigidBody(ball.get()); }

    double energy() const {
        const btVector3 g = w.world.getGravity();
        return spot->mechanicalEnergy(g) + kineticEnergy(*ball) - double(g.dot(ball->getCenterOfMassPosition())) * kBallMass;
    }
};

struct Measured {
    double fastest = 0, energyStart = 0, energyMost = 0;
};

Measured run(SpotScene& s, int steps) {
    Measured r;
    r.energyStart = r.energyMost = s.energy();
    for (int i = 0; i < steps; ++i) {
        s.w.step(1);
        r.fastest = std::max(r.fastest, s.spot->fastestPieces().centre);
        r.energyMost = std::max(r.energyMost, s.energy());
    }
    return r;
}

// Every split hands on mass and momenta; what breaks off the anchored (static) body starts at
// rest. Returns how many splits were of moving pieces.
int expectSplitsConserve(const std::vector<LatticeSystem::SplitRecord>& records) {
    int moving = 0;
    for (const auto& rec : records) {
        if (rec.parent.velocity.isZero() && rec.parent.angularVelocity.isZero()) {
            for (const auto& part : rec.parts) EXPECT_TRUE(part.velocity.isZero() && part.angularVelocity.isZero());
            continue;
        }
        ++moving;
        test::expectPartsConserveTheWhole(rec.parent, rec.parts);
    }
    return moving;
}

TEST(RealShape, SpotAnchoredByItsHoovesBreaksUnderAHitWithinTheSpeedBound) {
    SpotScene s(10.0, true, true);
    EXPECT_EQ(s.spot->sliverCount(), 58);
    EXPECT_FALSE(s.spot->settings().fixedTets.empty());
    const Measured r = run(s, 90);
    EXPECT_GT(s.spot->pieceCount(), 5) << "the hit should break it";
    // A contact can at most give hitSpeedFactor (2) times the speed of what hit it; gravity
    // adds 9.81 m/s² × 0.375 s.
    const double bound = s.spot->settings().hitSpeedFactor * s.ballSpeed + 9.81 * 90 / 240.0;
    EXPECT_LT(r.fastest, bound);
    // Breaking and contacts take energy away; taking back a breaking body's contact impulses
    // gives a little back (tests/demos/lattice_scenes_test.cpp: up to 4% on the table).
    EXPECT_LT(r.energyMost, 1.05 * r.energyStart) << "energy went from " << r.energyStart << " J up to " << r.energyMost;
    EXPECT_NEAR(s.spot->currentMass(), s.spot->initialMass(), 1e-9 * s.spot->initialMass());
    expectSplitsConserve(s.plugin.lattices().takeSplitRecords());
}

TEST(RealShape, SpotDroppedAndHitBreaksWithinTheSpeedBoundWithoutReplay) {
    // Free, 1.5 m up, hit by the ball as it falls (5.4 m/s at the ground), with the contact
    // impulses of a breaking piece kept (LatticeSettings::replayImpacts off). With the replay
    // (the default) the bound does not hold here: taking back the impulses of a breaking
    // three-tet piece spun it to 486 rad/s within one step, after that step's speed and spin
    // limits, and its parts flew at 34-41 m/s for two steps (LatticeSystem::replayImpacts,
    // reported in the issue 19 notes).
    SpotScene s(10.0, false, false, 1.5);
    const Measured r = run(s, 160);
    EXPECT_GT(s.spot->pieceCount(), 5) << "the hit and the fall should break it";
    const double bound = s.spot->settings().hitSpeedFactor * (s.ballSpeed + 9.81 * 160 / 240.0);
    EXPECT_LT(r.fastest, bound);
    EXPECT_LT(r.energyMost, 1.05 * r.energyStart) << "energy went from " << r.energyStart << " J up to " << r.energyMost;
    EXPECT_NEAR(s.spot->currentMass(), s.spot->initialMass(), 1e-9 * s.spot->initialMass());
    EXPECT_GT(expectSplitsConserve(s.plugin.lattices().takeSplitRecords()), 0);
}

} // namespace
} // namespace shatter
