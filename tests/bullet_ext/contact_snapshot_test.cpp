// The contact snapshot: one copy per step of Bullet's manifolds, the impulses its solver
// applied, and how fast the bodies approached before the step.
#include <shatter/bullet_ext/ContactSnapshot.h>
#include "tests/support/TestWorld.h"

#include <gtest/gtest.h>

namespace shatter {
namespace {

// A ball of radius 0.1 m in the world (taken out of it again when the test ends).
struct Falling {
    btDiscreteDynamicsWorld& world;
    btSphereShape shape{0.1f};
    std::unique_ptr<btRigidBody> body;
    Falling(test::TestWorld& w, double mass, double height) : world(w.world) {
        btVector3 inertia;
        shape.calculateLocalInertia(btScalar(mass), inertia);
        body = std::make_unique<btRigidBody>(btScalar(mass), nullptr, &shape, inertia);
        body->setWorldTransform(btTransform(btQuaternion::getIdentity(), btVector3(0, btScalar(height), 0)));
        w.world.addRigidBody(body.get());
    }
    ~Falling() { world.removeRigidBody(body.get()); }
};

TEST(ContactSnapshot, ARestingBodysImpulsesCarryItsWeightOverTheStep) {
    test::TestWorld w;
    w.addGround();
    Falling ball(w, 10.0, 0.1);
    w.step(240);
    ContactSnapshot snapshot;
    snapshot.capture(w.dispatcher);
    const auto pairs = snapshot.pairsOf(ball.body.get());
    ASSERT_EQ(pairs.size(), 1u);
    const ContactPair& pair = snapshot.pairs()[pairs[0]];
    EXPECT_TRUE(pair.solved);
    EXPECT_EQ(pair.other(ball.body.get()), w.ground.get());
    EXPECT_EQ(pair.rigid(ball.body.get()), ball.body.get());
    btVector3 impulse(0, 0, 0);
    for (const ContactPoint& p : snapshot.points(pair)) {
        impulse += ContactSnapshot::impulseOn(pair, p, ball.body.get());
        EXPECT_EQ(ContactSnapshot::primitiveOn(pair, p, ball.body.get()), -1); // not a group shape
        EXPECT_NEAR(ContactSnapshot::pushOn(pair, p, ball.body.get()).y(), 1.0, 1e-6);
    }
    // At rest the ground's push over one step of 1/240 s is the weight's impulse m g dt
    // (Bullet's solver converges to it within its iteration tolerance: 1% here).
    EXPECT_NEAR(double(impulse.y()), 10.0 * 9.81 / 240.0, 0.01 * 10.0 * 9.81 / 240.0);
    EXPECT_NEAR(double(impulse.x()), 0.0, 1e-6);
}

TEST(ContactSnapshot, TheApproachSpeedIsTheSpeedBeforeTheImpactStep) {
    test::TestWorld w;
    w.addGround();
    Falling ball(w, 2.0, 0.6); // falls 0.5 m: about 3.1 m/s at impact
    ContactSnapshot snapshot;
    for (int step = 0; step < 240; ++step) {
        const double speedBefore = -double(ball.body->getLinearVelocity().y());
        snapshot.recordMotion(w.world);
        w.step(1);
        snapshot.capture(w.dispatcher);
        const auto pairs = snapshot.pairsOf(ball.body.get());
        if (pairs.empty()) continue;
        const ContactPair& pair = snapshot.pairs()[pairs[0]];
        double fastest = 0;
        for (const ContactPoint& p : snapshot.points(pair)) fastest = std::max(fastest, ContactSnapshot::approachSpeed(pair, p));
        // Bullet's speculative contact may appear a step early, when the ball still falls
        // freely: then the speed before is one gravity step slower than at impact.
        EXPECT_NEAR(fastest, speedBefore, 1e-4) << "step " << step;
        EXPECT_GT(fastest, 3.0);
        EXPECT_GT(-double(ball.body->getLinearVelocity().y()), -0.5); // the solver stopped it (or will)
        return;
    }
    FAIL() << "the ball never touched the ground";
}

TEST(ContactSnapshot, PairsOfABodyThatLeftTheWorldAreGone) {
    test::TestWorld w;
    w.addGround();
    Falling ball(w, 1.0, 0.1);
    w.step(10);
    ContactSnapshot snapshot;
    snapshot.capture(w.dispatcher);
    ASSERT_EQ(snapshot.pairsOf(ball.body.get()).size(), 1u);
    snapshot.forget(ball.body.get());
    EXPECT_TRUE(snapshot.pairs()[snapshot.pairsOf(ball.body.get())[0]].gone);
}

TEST(ContactSnapshot, UndoingAnImpulseGivesTheBodyItsVelocityBack) {
    test::TestWorld w;
    w.addGround();
    Falling ball(w, 1.0, 0.1);
    w.step(60);
    ContactSnapshot snapshot;
    snapshot.capture(w.dispatcher);
    const ContactPair& pair = snapshot.pairs()[snapshot.pairsOf(ball.body.get())[0]];
    const btVector3 before = ball.body->getLinearVelocity();
    btVector3 impulse(0, 0, 0);
    for (const ContactPoint& p : snapshot.points(pair)) {
        impulse += ContactSnapshot::impulseOn(pair, p, ball.body.get());
        ContactSnapshot::undoImpulse(pair, p); // the static ground is not moved
    }
    const btVector3 change = ball.body->getLinearVelocity() - before;
    EXPECT_NEAR(double(change.y()), -double(impulse.y()) / 1.0, 1e-6);
    EXPECT_EQ(w.ground->getLinearVelocity(), btVector3(0, 0, 0));
}

} // namespace
} // namespace shatter
