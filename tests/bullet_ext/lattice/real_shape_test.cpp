// A real shape (issue 19): Spot, tetrahedralized by TetGen without a quality bound (the shipped
// demos/assets/spot_tets.ele: 2,281 tets, 58 slivers; and, where the tetgen program is
// installed, the full surface: 10,274 tets, 1,599 slivers), anchored by its hooves (a region in
// world coordinates) and hit by a ball, and dropped free and hit, with the default settings
// (the impulse replay after a break on). No fragment moves faster than the fastest body that
// hit it plus what its share of the released energy allows: the rigid links store no energy,
// and the most a contact can give is an elastic bounce off a much heavier body, twice the
// hitter's speed (LatticeSettings::hitSpeedFactor); gravity adds g·t. Energy does not grow,
// mass is kept to 1e-9 and every split of a moving piece hands on its momenta
// (tests/support/PartsConserve.h). (That no sliver breaks off alone is tested on the lattice:
// tests/lattice/slivers_test.cpp. In these scenes none did even unbound.)
#include <shatter/bullet_ext/Plugin.h>
#include <shatter/bullet_ext/VisualBody.h>
#include <shatter/bullet_ext/lattice/LatticeBody.h>
#include <shatter/bullet_ext/lattice/LatticeSystem.h>
#include <shatter/plugin/geometry/ObjFile.h>
#include <shatter/plugin/lattice/AnchorRegion.h>
#include <shatter/plugin/lattice/Fragments.h>
#include <shatter/plugin/lattice/TetGenProgram.h>
#include <shatter/plugin/lattice/TetGenReader.h>
#include "tests/support/PartsConserve.h"
#include "tests/support/TestWorld.h"

#include <gtest/gtest.h>

#include <memory>

namespace shatter {
namespace {

lattice::TetMesh spotMesh() { return lattice::readTetGen(std::string(SHATTER_SOURCE_DIR) + "/demos/assets/spot_tets.ele"); }

// What a user with Debian's tetgen gets from Spot's full surface with -p alone (the mesh).
lattice::TetMesh spotMesh10k() {
    const geometry::ObjFile obj = geometry::loadObj(std::string(SHATTER_SOURCE_DIR) + "/demos/assets/spot.obj");
    std::vector<std::vector<int>> faces;
    for (const auto& object : obj.objects)
        for (const auto& f : object.faces) faces.push_back(f.vertices);
    lattice::TetGenProgramOptions o;
    o.radiusEdgeRatio = 0;
    return lattice::tetrahedralize("spot", obj.positions, faces, o);
}

// Spot standing on the ground (its lowest node at y = 0) and a 0.12 m ball flying at its flank.
struct SpotScene {
    static constexpr btScalar kBallMass = 80;
    test::TestWorld w;
    Plugin plugin{w.world};
    LatticeBody* spot = nullptr;
    btSphereShape ballShape{0.12f};
    std::unique_ptr<btRigidBody> ball;
    double ballSpeed;

    SpotScene(const lattice::TetMesh& mesh, double speed, bool anchored, double lift = 0.0,
              double minFragmentSize = LatticeSettings{}.minFragmentSize)
        : ballSpeed(speed) {
        w.addGround();
        w.world.getSolverInfo().m_splitImpulse = 1;
        w.world.getSolverInfo().m_splitImpulsePenetrationThreshold = 0;
        LatticeSettings s;
        s.name = "spot";
        s.minFragmentSize = minFragmentSize;
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
    SpotScene s(spotMesh(), 10.0, true);
    EXPECT_EQ(s.spot->sliverCount(), 58);
    EXPECT_FALSE(s.spot->settings().fixedTets.empty());
    const int steps = 90;
    const Measured r = run(s, steps);
    EXPECT_GT(s.spot->pieceCount(), 5) << "the hit should break it";
    const double bound = s.spot->settings().hitSpeedFactor * s.ballSpeed + 9.81 * steps / 240.0;
    EXPECT_LT(r.fastest, bound);
    // Breaking and contacts take energy away (measured: never above the start).
    EXPECT_LT(r.energyMost, 1.01 * r.energyStart) << "energy went from " << r.energyStart << " J up to " << r.energyMost;
    EXPECT_NEAR(s.spot->currentMass(), s.spot->initialMass(), 1e-9 * s.spot->initialMass());
    expectSplitsConserve(s.plugin.lattices().takeSplitRecords());
}

// `mesh` lifted by `lift`, free, hit by the ball at `speed` as it falls, for 160 steps.
void expectDroppedAndHitWithinTheBound(const lattice::TetMesh& mesh, double lift, double speed, int steps) {
    SCOPED_TRACE("lifted " + std::to_string(lift) + " m, ball at " + std::to_string(speed) + " m/s");
    SpotScene s(mesh, speed, false, lift);
    EXPECT_TRUE(s.spot->settings().replayImpacts);
    const Measured r = run(s, steps);
    EXPECT_GT(s.spot->pieceCount(), 5) << "the hit and the fall should break it";
    // What hits a piece moves at most at the ball's speed plus what it fell.
    const double bound = s.spot->settings().hitSpeedFactor * (s.ballSpeed + 9.81 * steps / 240.0);
    EXPECT_LT(r.fastest, bound);
    // Measured: never above the start.
    EXPECT_LT(r.energyMost, 1.01 * r.energyStart) << "energy went from " << r.energyStart << " J up to " << r.energyMost;
    EXPECT_NEAR(s.spot->currentMass(), s.spot->initialMass(), 1e-9 * s.spot->initialMass());
    EXPECT_GT(expectSplitsConserve(s.plugin.lattices().takeSplitRecords()), 0);
}

TEST(RealShape, SpotDroppedAndHitBreaksWithinTheSpeedBound) {
    // Before the replay took a breaking piece's impulses back about the centres the solver
    // used (not where the step had moved them) and from its whole contact island, pieces flew
    // at 37 m/s here (bound 25) and 64 m/s (bound 37), a three-tet piece of a 1.5 m drop was
    // spun to 486 rad/s within one step, and energy rose by up to 2.4%.
    const lattice::TetMesh mesh = spotMesh();
    expectDroppedAndHitWithinTheBound(mesh, 1.0, 6.0, 160);
    expectDroppedAndHitWithinTheBound(mesh, 1.0, 12.0, 160);
}

// The sliver-rich mesh, dropped and hit (before the fix: 16.9 m/s against a bound of
// 33.8, energy +2.2%; its statue in the wall demo flung single tets at 68 m/s against 19). Only
// where the external program is installed (it is not a dependency).
TEST(RealShape, SliverRichSpotDroppedAndHitBreaksWithinTheSpeedBound) {
    if (!lattice::tetgenAvailable()) GTEST_SKIP() << "tetgen is not installed";
    const lattice::TetMesh mesh = spotMesh10k();
    ASSERT_EQ(mesh.tets.size(), 10274u);
    expectDroppedAndHitWithinTheBound(mesh, 1.0, 12.0, 120);
}

// The minimum fragment size (LatticeSettings::minFragmentSize) on the statue of the issue's
// 10,274-tet mesh hit hard (30 m/s): with 15 cm, more than the tets of its flank, no loose piece
// is smaller, the hit makes far fewer pieces than with single tets coming loose (measured 15
// against 38), and mass and momenta are kept through every split. (The default 5 cm is below
// most tets of this mesh's flank.) Only where the external program is installed.
TEST(RealShape, FineSpotStatueShedsNoPieceBelowTheMinimumFragmentSize) {
    if (!lattice::tetgenAvailable()) GTEST_SKIP() << "tetgen is not installed";
    const lattice::TetMesh mesh = spotMesh10k();
    auto pieces = [&](double minSize) {
        SpotScene s(mesh, 30.0, true, 0.0, minSize);
        run(s, 60);
        for (const auto& p : s.spot->pieces()) {
            if (p.lattice.anchored) continue;
            EXPECT_GE(lattice::pieceSize(s.spot->lattice(), p.lattice.particles, p.mass.centerOfMass), minSize);
        }
        EXPECT_NEAR(s.spot->currentMass(), s.spot->initialMass(), 1e-9 * s.spot->initialMass());
        expectSplitsConserve(s.plugin.lattices().takeSplitRecords());
        return s.spot->pieceCount();
    };
    const int merged = pieces(0.15), singles = pieces(0.0);
    EXPECT_GT(merged, 3) << "the hit should break it";
    EXPECT_LT(2 * merged, singles);
}

} // namespace
} // namespace shatter
