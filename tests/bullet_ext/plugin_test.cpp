// shatter::Plugin as an application sees it: attach, callbacks kept, events, joints, detach.
#include <shatter/bullet_ext/Convert.h>
#include <shatter/bullet_ext/Plugin.h>
#include "tests/support/TestWorld.h"

#include <BulletCollision/CollisionDispatch/btCollisionObjectWrapper.h>
#include <BulletCollision/CollisionDispatch/btConvexConcaveCollisionAlgorithm.h>
#include <BulletDynamics/ConstraintSolver/btHingeConstraint.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

using namespace shatter;
using shatter::test::at;

namespace {

geometry::PhysicalMesh boxMesh(const std::string& name, double hx, double hy, double hz) {
    std::vector<Eigen::Vector3d> v;
    for (int i = 0; i < 8; ++i) v.emplace_back(i & 1 ? hx : -hx, i & 2 ? hy : -hy, i & 4 ? hz : -hz);
    const std::vector<std::vector<int>> f = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    return geometry::buildPhysicalMesh(name, v, f);
}


struct TickLog {
    int calls = 0;
    void* userInfoSeen = nullptr;
};

void appTick(btDynamicsWorld* world, btScalar) {
    auto* log = static_cast<TickLog*>(world->getWorldUserInfo());
    log->calls++;
    log->userInfoSeen = world->getWorldUserInfo();
}

std::string objText() {
    // Two planks and a hinge box along z at x = 0 (see demos/assets/hinged_planks.obj).
    return R"(o plankA
v -0.7 -0.02 -0.08
v 0 -0.02 -0.08
v -0.7 0.02 -0.08
v 0 0.02 -0.08
v -0.7 -0.02 0.08
v 0 -0.02 0.08
v -0.7 0.02 0.08
v 0 0.02 0.08
f 1 3 4 2
f 5 6 8 7
f 1 2 6 5
f 3 7 8 4
f 1 5 7 3
f 2 4 8 6
o plankB
v 0 -0.02 -0.08
v 0.7 -0.02 -0.08
v 0 0.02 -0.08
v 0.7 0.02 -0.08
v 0 -0.02 0.08
v 0.7 -0.02 0.08
v 0 0.02 0.08
v 0.7 0.02 0.08
f 9 11 12 10
f 13 14 16 15
f 9 10 14 13
f 11 15 16 12
f 9 13 15 11
f 10 12 16 14
o joint.hinge.plankA.plankB
v -0.015 -0.025 -0.09
v 0.015 -0.025 -0.09
v -0.015 0.025 -0.09
v 0.015 0.025 -0.09
v -0.015 -0.025 0.09
v 0.015 -0.025 0.09
v -0.015 0.025 0.09
v 0.015 0.025 0.09
f 17 19 20 18
f 21 22 24 23
f 17 18 22 21
f 19 23 24 20
f 17 21 23 19
f 18 20 24 22
)";
}

} // namespace

TEST(Plugin, KeepsTheApplicationsTickCallbackAndUserInfo) {
    test::TestWorld w;
    TickLog log;
    w.world.setInternalTickCallback(appTick, &log);
    {
        Plugin plugin(w.world);
        plugin.addVisualBody(boxMesh("box", 0.1, 0.1, 0.1), {}, at(0, 1, 0));
        w.step(10);
        EXPECT_EQ(log.calls, 10);
        EXPECT_EQ(w.world.getWorldUserInfo(), &log);
        EXPECT_NEAR(plugin.time(), 10.0 / 240, 1e-6); // Shatter's own hook ran every internal step too
    }
    w.step(5); // detached by the destructor: the app's callback still runs
    EXPECT_EQ(log.calls, 15);
    EXPECT_EQ(log.userInfoSeen, &log);
}

TEST(Plugin, DetachRemovesEverythingAndRestoresTheDispatcher) {
    test::TestWorld w;
    const int before = w.world.getNumCollisionObjects();
    Plugin plugin(w.world);
    VisualBody& body = plugin.addVisualBody(boxMesh("box", 0.1, 0.1, 0.1), {}, at(0, 1, 0));
    btBoxShape box(btVector3(0.1f, 0.1f, 0.1f));
    btCollisionObject other;
    other.setCollisionShape(&box);
    auto algorithmFor = [&](const btCollisionObject& group) {
        btCollisionObjectWrapper a(nullptr, group.getCollisionShape(), &group, group.getWorldTransform(), -1, -1);
        btCollisionObjectWrapper b(nullptr, &box, &other, other.getWorldTransform(), -1, -1);
        btCollisionAlgorithm* algo = w.dispatcher.findAlgorithm(&a, &b, nullptr, BT_CONTACT_POINT_ALGORITHMS);
        const bool bullets = dynamic_cast<btConvexConcaveCollisionAlgorithm*>(algo) != nullptr;
        algo->~btCollisionAlgorithm();
        w.dispatcher.freeCollisionAlgorithm(algo);
        return bullets;
    };
    EXPECT_FALSE(algorithmFor(body.rigidBody())) << "Shatter's algorithm should handle group vs box";
    EXPECT_EQ(w.world.getNumCollisionObjects(), before + 2); // the body and the plugin's watch object
    // A group-shaped object that outlives the detach, to ask the dispatcher afterwards.
    const auto kept = boxMesh("kept", 0.1, 0.1, 0.1);
    GroupShape shape(kept.primitives, 0.001);
    btCollisionObject groupCopy;
    groupCopy.setCollisionShape(&shape);
    plugin.detach();
    EXPECT_FALSE(plugin.attached());
    EXPECT_EQ(w.world.getNumCollisionObjects(), before);
    EXPECT_TRUE(plugin.bodies().empty());
    EXPECT_TRUE(algorithmFor(groupCopy)) << "the configuration's own algorithm should be back";
    plugin.detach(); // idempotent
    EXPECT_THROW(plugin.addVisualBody(boxMesh("late", 0.1, 0.1, 0.1), {}, at(0, 1, 0)), InputError);
}

TEST(Plugin, EventsReportBodiesJointsAndBreaks) {
    test::TestWorld w;
    w.addGround();
    Plugin plugin(w.world);
    const auto object = geometry::buildPhysicalObject(geometry::parseObj(objText(), "planks.obj"));
    ASSERT_EQ(object.bodies.size(), 2u);
    ASSERT_EQ(object.joints.size(), 1u);
    BodySettings settings;
    settings.jointBreakingImpulse = 0.05; // N·s: landing on one end breaks it (free fall alone does not)
    const btTransform tilted(btQuaternion(btVector3(0, 0, 1), btScalar(0.4)), btVector3(0, 1.0f, 0));
    auto added = plugin.addObject(object, settings, tilted);
    auto events = plugin.takeEvents();
    ASSERT_EQ(events.size(), 3u);
    EXPECT_EQ(events[0].type, EventType::BodyAdded);
    EXPECT_EQ(events[1].type, EventType::BodyAdded);
    EXPECT_EQ(events[2].type, EventType::JointAdded);
    EXPECT_EQ(events[2].name, "joint.hinge.plankA.plankB");
    EXPECT_TRUE(plugin.takeEvents().empty()) << "the queue is drained";
    w.step(240);
    events = plugin.takeEvents();
    ASSERT_EQ(events.size(), 1u);
    EXPECT_EQ(events[0].type, EventType::JointBroken);
    EXPECT_GT(events[0].time, 0.0);
    EXPECT_TRUE(added.joints[0]->broken());
    plugin.removeBody(*added.bodies[0]);
    events = plugin.takeEvents();
    ASSERT_EQ(events.size(), 1u);
    EXPECT_EQ(events[0].type, EventType::BodyRemoved);
    EXPECT_EQ(events[0].name, "plankA");
    EXPECT_TRUE(plugin.joints().empty()) << "a removed body takes its joints with it";
}

TEST(Plugin, HingeTurnsAboutTheJointBoxsLongAxis) {
    test::TestWorld w;
    w.world.setGravity(btVector3(0, 0, 0));
    Plugin plugin(w.world);
    const auto object = geometry::buildPhysicalObject(geometry::parseObj(objText(), "planks.obj"));
    const btTransform pose(btQuaternion(btVector3(0, 1, 0), btScalar(0.5)), btVector3(0, 2, 0));
    auto added = plugin.addObject(object, {}, pose);
    btRigidBody& a = added.bodies[0]->rigidBody();
    btRigidBody& b = added.bodies[1]->rigidBody();
    const auto& hinge = static_cast<btHingeConstraint&>(added.joints[0]->constraint());
    auto hingeAxis = [&] { return a.getWorldTransform().getBasis() * hinge.getAFrame().getBasis().getColumn(2); };
    // The hinge axis is the joint box's long axis (box z), turned by the pose.
    const btVector3 axis = pose.getBasis() * btVector3(0, 0, 1);
    EXPECT_NEAR(double(std::abs(hingeAxis().dot(axis))), 1.0, 1e-6);
    // Spin plank B about the hinge axis and across it.
    b.setAngularVelocity(axis * 2 + pose.getBasis() * btVector3(1, 0, 0));
    w.step(120);
    // The pair tumbles as a whole, so the hinge axis now is where body A carries it.
    const btVector3 axisNow = hingeAxis();
    const btVector3 relative = b.getAngularVelocity() - a.getAngularVelocity();
    // Only the component about the hinge axis may remain (1e-3 rad/s: solver residual).
    EXPECT_LT((relative - axisNow * relative.dot(axisNow)).length(), 1e-3);
    EXPECT_GT(std::abs(double(relative.dot(axisNow))), 0.1);
}

TEST(Plugin, VisualMeshFollowsTheBody) {
    test::TestWorld w;
    Plugin plugin(w.world);
    const auto mesh = boxMesh("box", 0.3, 0.1, 0.2);
    VisualBody& body = plugin.addVisualBody(mesh, {}, at(0, 5, 0));
    body.rigidBody().setAngularVelocity(btVector3(1, 2, 3));
    w.step(60);
    const auto& visual = body.visualMesh();
    ASSERT_EQ(visual.positions.size(), mesh.visual.positions.size());
    EXPECT_EQ(visual.faces, mesh.visual.faces);
    const Eigen::Isometry3d t = toEigen(body.meshTransform());
    for (size_t i = 0; i < visual.positions.size(); ++i)
        EXPECT_LT((visual.positions[i] - t * mesh.visual.positions[i]).norm(), 1e-5) << "vertex " << i; // float precision
}

TEST(Plugin, BadPoseAndSettingsAreErrorsNamingTheBody) {
    test::TestWorld w;
    Plugin plugin(w.world);
    const auto mesh = boxMesh("crate", 0.1, 0.1, 0.1);
    try {
        plugin.addVisualBody(mesh, {}, at(0, std::nan(""), 0));
        FAIL() << "a NaN pose must be refused";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("crate"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("pose"), std::string::npos) << e.what();
    }
    BodySettings bad;
    bad.rigidBody.friction = -1;
    EXPECT_THROW(plugin.addVisualBody(mesh, bad, at(0, 1, 0)), InputError);
    EXPECT_TRUE(plugin.bodies().empty());
    EXPECT_EQ(w.world.getNumCollisionObjects(), 1); // the plugin's watch object only
}

// Bullet's pairs of a body in the world keep the algorithms made for its group shape, so it
// may change what it collides as only before it enters.
TEST(Plugin, ABodyInTheWorldCannotChangeWhatItCollidesAs) {
    test::TestWorld w;
    Plugin plugin(w.world);
    VisualBody& body = plugin.addVisualBody(boxMesh("crate", 0.1, 0.1, 0.1), {}, at(0, 1, 0));
    const btCollisionShape* before = body.rigidBody().getCollisionShape();
    btBoxShape other(btVector3(0.1f, 0.1f, 0.1f));
    try {
        body.collideAs(other);
        FAIL() << "collideAs on a body in the world must be refused";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("crate"), std::string::npos) << e.what();
    }
    EXPECT_EQ(body.rigidBody().getCollisionShape(), before);
}

TEST(Plugin, MassAndInertiaComeFromThePrimitives) {
    test::TestWorld w;
    Plugin plugin(w.world);
    const double hx = 0.5, hy = 0.1, hz = 0.2;
    BodySettings settings;
    VisualBody& body = plugin.addVisualBody(boxMesh("slab", hx, hy, hz), settings, at(0, 1, 0));
    const double m = 1000.0 * 8 * hx * hy * hz;
    EXPECT_NEAR(1.0 / double(body.rigidBody().getInvMass()), m, 1e-3 * m);
    // Bullet holds the principal moments; as a set they must match the box's closed form.
    std::vector<double> expected = {m / 3 * (hy * hy + hz * hz), m / 3 * (hx * hx + hz * hz), m / 3 * (hx * hx + hy * hy)};
    const btVector3 inv = body.rigidBody().getInvInertiaDiagLocal();
    std::vector<double> got = {1.0 / inv.x(), 1.0 / inv.y(), 1.0 / inv.z()};
    std::sort(expected.begin(), expected.end());
    std::sort(got.begin(), got.end());
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(got[i], expected[i], 1e-4 * expected[i]);
}
