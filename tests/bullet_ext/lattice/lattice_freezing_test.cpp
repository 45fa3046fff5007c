// Freezing of resting lattice pieces (LatticeSettings::freezeAtRest): a piece at rest becomes a
// static body and comes back as the same dynamic body when something hits it, when what it
// rests on moves away, or when the application asks; a hit plays out as if it had never frozen.
#include <shatter/bullet_ext/lattice/LatticeBody.h>
#include <shatter/bullet_ext/lattice/LatticeSystem.h>
#include <shatter/bullet_ext/Plugin.h>
#include <shatter/bullet_ext/VisualBody.h>
#include <shatter/plugin/lattice/TetGenerators.h>
#include "tests/bullet_ext/lattice/WallScene.h"
#include "tests/support/TestWorld.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <memory>

namespace shatter {
namespace {

const btTransform kCubeOnGround(btQuaternion::getIdentity(), btVector3(0, 0.0505f, 0));

// A 10 cm cube of six tets (one convex piece) set down in a world with a ground.
struct CubeScene {
    test::TestWorld w;
    Plugin plugin{w.world};
    LatticeBody* cube = nullptr;

    explicit CubeScene(bool freeze, const btTransform& pose = kCubeOnGround,
                       double wakeMassRatio = RestSettings{}.wakeMassRatio) {
        w.addGround();
        LatticeSettings s;
        s.rest.freezeAtRest = freeze;
        s.rest.wakeMassRatio = wakeMassRatio;
        cube = &plugin.addLatticeBody(lattice::tetBox({0.1, 0.1, 0.1}, {1, 1, 1}), s, pose);
    }
    const LatticeBody::Piece& piece() const { return cube->pieces()[0]; }
    btRigidBody& body() const { return cube->pieces()[0].body->rigidBody(); }
};

std::unique_ptr<btRigidBody> makeBall(btSphereShape& shape, double mass, const btVector3& at, const btVector3& velocity) {
    btVector3 inertia;
    shape.calculateLocalInertia(btScalar(mass), inertia);
    auto ball = std::make_unique<btRigidBody>(btScalar(mass), nullptr, &shape, inertia);
    ball->setWorldTransform(btTransform(btQuaternion::getIdentity(), at));
    ball->setLinearVelocity(velocity);
    return ball;
}

TEST(LatticeFreezing, ARestingPieceFreezesAndThawsAsTheSameBody) {
    CubeScene s(true);
    const btScalar mass = s.body().getMass();
    const btVector3 inertia = s.body().getLocalInertia();
    const int group = s.body().getBroadphaseHandle()->m_collisionFilterGroup;
    const int mask = s.body().getBroadphaseHandle()->m_collisionFilterMask;
    s.w.step(240); // 1 s: at rest after sleepAfter
    ASSERT_TRUE(s.piece().frozen);
    EXPECT_TRUE(s.body().isStaticObject());
    EXPECT_EQ(s.body().getActivationState(), ISLAND_SLEEPING);
    EXPECT_EQ(s.body().getBroadphaseHandle()->m_collisionFilterGroup, int(btBroadphaseProxy::StaticFilter));
    EXPECT_NEAR(s.body().getCenterOfMassPosition().y(), 0.05f, 0.002f);
    EXPECT_GT(s.plugin.lattices().timing().frozen, 0);
    EXPECT_NEAR(s.cube->currentMass(), s.cube->initialMass(), 1e-12 * s.cube->initialMass()); // still counted

    ASSERT_TRUE(s.plugin.lattices().thaw(s.body()));
    EXPECT_FALSE(s.plugin.lattices().thaw(s.body())); // not frozen any more
    EXPECT_FALSE(s.piece().frozen);
    EXPECT_FALSE(s.body().isStaticOrKinematicObject());
    EXPECT_TRUE(s.body().isActive());
    EXPECT_EQ(s.body().getMass(), mass);
    EXPECT_EQ(s.body().getLocalInertia(), inertia);
    EXPECT_EQ(s.body().getBroadphaseHandle()->m_collisionFilterGroup, group);
    EXPECT_EQ(s.body().getBroadphaseHandle()->m_collisionFilterMask, mask);
    EXPECT_EQ(s.body().getGravity(), s.w.world.getGravity());
    s.w.step(24); // dynamic again: it still rests where it was
    EXPECT_NEAR(s.body().getCenterOfMassPosition().y(), 0.05f, 0.002f);
    EXPECT_LT(s.body().getLinearVelocity().length(), 0.05f);
}

TEST(LatticeFreezing, APieceInFlightNeverRestsNotEvenAtTheTopOfAThrow) {
    // Thrown straight up at 2 m/s, a cube stays within sleepDrift (5 mm) of the top of its
    // flight for 0.05 s (g t²/8 = 3 mm), slower than Bullet's sleeping thresholds: with the
    // debris' short sleepAfter it would freeze there if only its drift counted.
    test::TestWorld w;
    Plugin plugin{w.world};
    w.addGround();
    LatticeSettings s;
    s.rest.sleepAfter = 0.05;
    LatticeBody& cube = plugin.addLatticeBody(lattice::tetBox({0.1, 0.1, 0.1}, {1, 1, 1}), s,
                                              btTransform(btQuaternion::getIdentity(), btVector3(0, 0.5f, 0)));
    btRigidBody& body = cube.pieces()[0].body->rigidBody();
    body.setLinearVelocity(btVector3(0, 2, 0));
    double highest = 0.0;
    for (int step = 0; step < 480; ++step) {
        w.step(1);
        highest = std::max(highest, double(body.getCenterOfMassPosition().y()));
        if (cube.pieces()[0].frozen) {
            EXPECT_LT(body.getCenterOfMassPosition().y(), 0.06f) << "frozen in flight at step " << step;
            break;
        }
    }
    EXPECT_GT(highest, 0.65); // it flew (0.5 m + 2² / 2g)
    EXPECT_TRUE(cube.pieces()[0].frozen); // and froze once down
}

TEST(LatticeFreezing, WithoutFreezingAPieceOnlySleeps) {
    CubeScene s(false);
    s.w.step(720);
    EXPECT_FALSE(s.piece().frozen);
    EXPECT_FALSE(s.body().isStaticObject());
    EXPECT_EQ(s.body().getActivationState(), ISLAND_SLEEPING); // Bullet's own sleep, after 2 s
}

// Where the cube is 0.5 s after a 1 kg ball rolling at 2 m/s hits it, and how fast the ball
// goes then; the cube frozen or not when hit.
struct HitOutcome {
    btVector3 cube, ball;
};
HitOutcome hitCube(bool freeze) {
    CubeScene s(freeze);
    s.w.step(240);
    EXPECT_EQ(s.piece().frozen, freeze);
    btSphereShape shape(0.05f);
    auto ball = makeBall(shape, 1.0, btVector3(-0.3f, 0.05f, 0), btVector3(2, 0, 0));
    s.w.world.addRigidBody(ball.get());
    s.w.step(120);
    HitOutcome out{s.body().getCenterOfMassPosition(), ball->getLinearVelocity()};
    EXPECT_EQ(s.plugin.lattices().timing().thawed > 0, freeze);
    s.w.world.removeRigidBody(ball.get());
    return out;
}

TEST(LatticeFreezing, AHitWakesAFrozenPieceAndPlaysOutAsWithoutFreezing) {
    const HitOutcome frozen = hitCube(true), awake = hitCube(false);
    // The 1 kg ball sets the 1.7 kg cube sliding at ~0.7 m/s; friction (0.6 × 0.6) stops it
    // after ~7 cm.
    EXPECT_GT(awake.cube.x(), 0.04f);
    // The frozen cube met the ball as a static body for one step of 1/240 s, whose impulse was
    // taken back: the outcome is that of the cube that never froze, within 1 cm (one step at 2 m/s).
    EXPECT_NEAR(frozen.cube.x(), awake.cube.x(), 0.01f);
    EXPECT_NEAR(frozen.ball.x(), awake.ball.x(), 0.05f);
}

TEST(LatticeFreezing, ASlowTouchDoesNotWakeAFrozenPiece) {
    CubeScene s(true);
    s.w.step(240);
    ASSERT_TRUE(s.piece().frozen);
    // A 0.5 kg ball set down on top of it from 1 mm: lands at ~0.14 m/s, below wakeSpeed.
    btSphereShape shape(0.03f);
    auto ball = makeBall(shape, 0.5, btVector3(0, 0.131f, 0), btVector3(0, 0, 0));
    s.w.world.addRigidBody(ball.get());
    s.w.step(120);
    EXPECT_TRUE(s.piece().frozen);
    EXPECT_NEAR(ball->getCenterOfMassPosition().y(), 0.13f, 0.002f); // it holds the ball up
    s.w.world.removeRigidBody(ball.get());
}

// Whether the frozen 1.7 kg cube wakes when a 10 g ball (0.6% of its mass) rolling at 2 m/s
// hits it, with RestSettings::wakeMassRatio `ratio`.
bool shardWakesCube(double ratio) {
    CubeScene s(true, kCubeOnGround, ratio);
    s.w.step(240);
    EXPECT_TRUE(s.piece().frozen);
    btSphereShape shape(0.01f);
    auto shard = makeBall(shape, 0.01, btVector3(-0.2f, 0.01f, 0), btVector3(2, 0, 0));
    s.w.world.addRigidBody(shard.get());
    s.w.step(120);
    EXPECT_LT(shard->getLinearVelocity().x(), 0.0f); // it met the cube and bounced back
    s.w.world.removeRigidBody(shard.get());
    return s.plugin.lattices().timing().thawed > 0;
}

TEST(LatticeFreezing, AShardFarLighterThanAFrozenPieceDoesNotWakeIt) {
    EXPECT_FALSE(shardWakesCube(0.02)); // the default: lighter than 2% of the piece
    EXPECT_TRUE(shardWakesCube(0.0));   // any hitter, as before wakeMassRatio
    EXPECT_TRUE(shardWakesCube(0.005)); // the shard is 0.6%
}

// Whether the frozen cube wakes when a 20 g box (1.2% of its mass) lying against its side,
// which it counted as a support when it froze, slides 10 cm away.
bool lightSupportWakesCube(double ratio) {
    btBoxShape pebbleShape(btVector3(0.01f, 0.01f, 0.01f));
    btVector3 inertia;
    pebbleShape.calculateLocalInertia(0.02f, inertia);
    btRigidBody pebble(0.02f, nullptr, &pebbleShape, inertia);
    pebble.setWorldTransform(btTransform(btQuaternion::getIdentity(), btVector3(0.0603f, 0.0101f, 0)));
    CubeScene s(true, kCubeOnGround, ratio);
    s.w.world.addRigidBody(&pebble);
    s.w.step(240);
    EXPECT_TRUE(s.piece().frozen);
    pebble.activate(true);
    pebble.setLinearVelocity(btVector3(1, 0, 0));
    s.w.step(60);
    EXPECT_GT(pebble.getCenterOfMassPosition().x(), 0.1f);
    s.w.world.removeRigidBody(&pebble);
    return s.plugin.lattices().timing().thawed > 0;
}

TEST(LatticeFreezing, ASupportFarLighterThanAFrozenPieceDoesNotWakeItWhenItMoves) {
    EXPECT_FALSE(lightSupportWakesCube(0.02));
    EXPECT_TRUE(lightSupportWakesCube(0.0)); // as before wakeMassRatio: it was a support
}

TEST(LatticeFreezing, AFrozenPieceWakesWhenWhatItRestsOnMovesAway) {
    // The cube rests on an application's box (dynamic), freezes there, and the box is pulled
    // out from under it: the cube must not hang in the air.
    btBoxShape boxShape(btVector3(0.2f, 0.05f, 0.2f));
    btVector3 inertia;
    boxShape.calculateLocalInertia(10, inertia);
    btRigidBody box(10, nullptr, &boxShape, inertia);
    box.setWorldTransform(btTransform(btQuaternion::getIdentity(), btVector3(0, 0.05f, 0)));
    CubeScene s(true, btTransform(btQuaternion::getIdentity(), btVector3(0, 0.1505f, 0)));
    s.w.world.addRigidBody(&box);
    s.w.step(240);
    ASSERT_TRUE(s.piece().frozen);
    EXPECT_NEAR(s.body().getCenterOfMassPosition().y(), 0.15f, 0.003f);
    box.activate(true);
    box.setLinearVelocity(btVector3(0, 0, 3));
    s.w.step(240);
    EXPECT_NEAR(s.body().getCenterOfMassPosition().y(), 0.05f, 0.003f); // fell to the ground
    EXPECT_GT(s.plugin.lattices().timing().thawed, 0);
    s.w.world.removeRigidBody(&box);
}

TEST(LatticeFreezing, AMovingKinematicBodyWakesTheFrozenPiecesItOverlaps) {
    CubeScene s(true);
    s.w.step(240);
    ASSERT_TRUE(s.piece().frozen);
    btBoxShape pusherShape(btVector3(0.05f, 0.05f, 0.2f));
    btRigidBody pusher(0, nullptr, &pusherShape);
    pusher.setCollisionFlags(pusher.getCollisionFlags() | btCollisionObject::CF_KINEMATIC_OBJECT);
    pusher.setActivationState(DISABLE_DEACTIVATION);
    s.w.world.addRigidBody(&pusher);
    for (int i = 0; i < 240 && s.piece().frozen; ++i) { // sweeps in at 0.5 m/s
        pusher.setWorldTransform(btTransform(btQuaternion::getIdentity(), btVector3(-0.3f + 0.5f * float(i) / 240, 0.06f, 0)));
        s.w.step(1);
    }
    EXPECT_FALSE(s.piece().frozen);
    EXPECT_LT(s.body().getCenterOfMassPosition().x(), 0.0f + 0.01f); // woken as the box reached it
    s.w.world.removeRigidBody(&pusher);
}

TEST(LatticeFreezing, APieceFallsWhenWhatItRestsOnBreaksOffAnAnchoredBody) {
    // A shelf (6 × 1 × 2 cells of 10 cm) anchored by its left third, a cube frozen on its free
    // end; a ball strikes the shelf's free end sideways and breaks it off: the cube must not
    // stay hanging where the shelf was. (Here the broken end also pushes into the cube, so
    // either that hit or the break itself wakes it.)
    CubeScene s(true, btTransform(btQuaternion::getIdentity(), btVector3(0.2f, 0.6005f, 0)));
    const lattice::TetMesh mesh = lattice::tetBox({0.6, 0.1, 0.2}, {6, 1, 2});
    LatticeSettings shelfSettings;
    shelfSettings.name = "shelf";
    shelfSettings.material.strength = 5e4; // weak enough that the struck end breaks off whole
    for (int t = 0; t < int(mesh.tets.size()); ++t) {
        double x = 0;
        for (int n : mesh.tets[t]) x += mesh.nodes[n].x() / 4;
        if (x < -0.1) shelfSettings.fixedTets.push_back(t);
    }
    LatticeBody& shelf = s.plugin.addLatticeBody(mesh, shelfSettings,
                                                 btTransform(btQuaternion::getIdentity(), btVector3(0, 0.5f, 0)));
    s.w.step(240);
    ASSERT_TRUE(s.piece().frozen);
    ASSERT_EQ(shelf.pieceCount(), 1);
    btSphereShape shape(0.05f);
    auto ball = makeBall(shape, 40.0, btVector3(0.25f, 0.5f, 0.4f), btVector3(0, 0, -16));
    s.w.world.addRigidBody(ball.get());
    s.w.step(60);
    EXPECT_GT(shelf.pieceCount(), 1);
    EXPECT_GT(s.plugin.lattices().timing().thawed, 0);
    s.w.step(240);
    EXPECT_LT(s.body().getCenterOfMassPosition().y(), 0.5f); // it fell with the broken end
    s.w.world.removeRigidBody(ball.get());
}

// The test wall broken by a 60 kg ball at 12 m/s, left for 3 s.
struct BrokenWall : test::WallScene {
    BrokenWall() : WallScene(12.0) { w.step(720); }
};

TEST(LatticeFreezing, ABrokenWallsLoosePiecesFreezeWhereTheyRest) {
    BrokenWall s;
    int loose = 0, frozen = 0;
    for (const auto& p : s.wall->pieces()) {
        loose += !p.lattice.anchored;
        frozen += p.frozen;
    }
    ASSERT_GT(loose, 12);
    EXPECT_GT(frozen, loose * 8 / 10);
    // Frozen where they really rest: woken all at once, no piece falls or slides away (a frozen
    // piece left hanging would drop 2 cm within the 1/15 s of fall below).
    for (const auto& p : s.wall->pieces())
        if (p.frozen) s.plugin.lattices().thaw(p.body->rigidBody());
    std::vector<btVector3> before;
    for (const auto& p : s.wall->pieces()) before.push_back(p.body->rigidBody().getCenterOfMassPosition());
    s.w.step(16);
    for (int i = 0; i < s.wall->pieceCount(); ++i)
        EXPECT_LT((s.wall->pieces()[i].body->rigidBody().getCenterOfMassPosition() - before[i]).length(), 0.02f)
            << s.wall->pieces()[i].body->name();
}

TEST(LatticeFreezing, FreezingIsDeterministic) {
    BrokenWall a, b;
    ASSERT_EQ(a.wall->pieceCount(), b.wall->pieceCount());
    for (int i = 0; i < a.wall->pieceCount(); ++i) {
        const btTransform& ta = a.wall->pieces()[i].body->rigidBody().getWorldTransform();
        const btTransform& tb = b.wall->pieces()[i].body->rigidBody().getWorldTransform();
        EXPECT_TRUE(ta.getOrigin() == tb.getOrigin() && ta.getBasis() == tb.getBasis()) << "piece " << i;
        EXPECT_EQ(a.wall->pieces()[i].frozen, b.wall->pieces()[i].frozen) << "piece " << i;
    }
}

} // namespace
} // namespace shatter
