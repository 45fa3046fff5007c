// Teardown as real Bullet applications write it: the world and its collaborators on the heap,
// Bullet's HelloWorld cleanup (delete every collision object in the world with its motion
// state, then the world), or CommonRigidBodyBase's (constraints first), in every order with
// the plugin. Each case must end without a crash, a double free or a leak; the sanitizer
// build (scripts/sanitize.sh) runs them under ASan and UBSan.
#include <shatter/shatter.h>
#include "tests/support/TestWorld.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>

namespace shatter {
namespace {

using test::at;

// The application: Bullet's HelloWorld example, unchanged (ground box, one dynamic sphere).
struct HelloWorldApp {
    btDefaultCollisionConfiguration* configuration = new btDefaultCollisionConfiguration();
    btCollisionDispatcher* dispatcher = new btCollisionDispatcher(configuration);
    btBroadphaseInterface* broadphase = new btDbvtBroadphase();
    btSequentialImpulseConstraintSolver* solver = new btSequentialImpulseConstraintSolver;
    btDiscreteDynamicsWorld* world = new btDiscreteDynamicsWorld(dispatcher, broadphase, solver, configuration);
    btAlignedObjectArray<btCollisionShape*> collisionShapes;

    HelloWorldApp() {
        world->setGravity(btVector3(0, -10, 0));
        btCollisionShape* groundShape = new btBoxShape(btVector3(50, 50, 50));
        collisionShapes.push_back(groundShape);
        addBody(groundShape, 0, btVector3(0, -50, 0));
        btCollisionShape* sphere = new btSphereShape(1);
        collisionShapes.push_back(sphere);
        addBody(sphere, 1, btVector3(2, 10, 0));
    }
    void addBody(btCollisionShape* shape, btScalar mass, const btVector3& origin) {
        btVector3 inertia(0, 0, 0);
        if (mass != 0) shape->calculateLocalInertia(mass, inertia);
        auto* state = new btDefaultMotionState(btTransform(btQuaternion::getIdentity(), origin));
        world->addRigidBody(new btRigidBody(btRigidBody::btRigidBodyConstructionInfo(mass, state, shape, inertia)));
    }
    void step(int frames) {
        for (int i = 0; i < frames; ++i) world->stepSimulation(1.f / 60.f, 10);
    }
    // CommonRigidBodyBase::exitPhysics removes and deletes the constraints first.
    void deleteConstraints() {
        for (int i = world->getNumConstraints() - 1; i >= 0; i--) {
            btTypedConstraint* constraint = world->getConstraint(i);
            world->removeConstraint(constraint);
            delete constraint;
        }
    }
    // HelloWorld's cleanup loop.
    void deleteObjects() {
        for (int i = world->getNumCollisionObjects() - 1; i >= 0; i--) {
            btCollisionObject* obj = world->getCollisionObjectArray()[i];
            btRigidBody* body = btRigidBody::upcast(obj);
            if (body && body->getMotionState()) delete body->getMotionState();
            world->removeCollisionObject(obj);
            delete obj;
        }
    }
    void deleteWorld() {
        for (int j = 0; j < collisionShapes.size(); j++) delete collisionShapes[j];
        collisionShapes.clear();
        delete world;
        delete solver;
        delete broadphase;
        delete dispatcher;
        delete configuration;
        world = nullptr;
    }
};

geometry::PhysicalObject asset(const std::string& name) {
    return geometry::buildPhysicalObject(geometry::loadObj(std::string(SHATTER_SOURCE_DIR) + "/demos/assets/" + name));
}


// Every kind of Shatter body, hit and broken before the teardown: a chair that shatters where
// it lands, two planks on a hinge joint that may break, a plastic torus dented where it lands,
// a soft bowl, and a lattice wall that a fast ball breaks into fragments (the ball is the
// application's).
void addShatterBodies(HelloWorldApp& app, Plugin& plugin) {
    BodySettings brittle;
    brittle.fracture.enabled = true;
    brittle.fracture.threshold = 1.0;
    plugin.addObject(asset("chair.obj"), brittle, at(-3, 1, 0));
    BodySettings breakable;
    breakable.jointBreakingImpulse = 5.0;
    plugin.addObject(asset("hinged_planks.obj"), breakable, at(3, 2, 0));
    BodySettings plastic;
    plastic.deformation = Deformation::Plastic;
    plastic.plastic.threshold = 1.0;
    plugin.addObject(asset("torus.obj"), plastic, at(0, 2, 3));
    BodySettings soft;
    soft.deformation = Deformation::Soft;
    plugin.addObject(asset("bowl.obj"), soft, at(0, 1, -3));
    LatticeSettings wall;
    wall.name = "wall";
    wall.material.strength = 1e4; // weak: HelloWorld steps at 1/60 s, where an impact's force is a quarter of the demos'
    const auto mesh = lattice::tetBox({1.0, 1.0, 0.2}, {5, 5, 1});
    double lowest = INFINITY;
    for (const auto& n : mesh.nodes) lowest = std::min(lowest, n.y());
    wall.fixedTets = lattice::tetsWithFaceOnPlane(mesh, {0, 1, 0}, lowest, 1e-6);
    plugin.addLatticeBody(mesh, wall, at(6, 0.5, 6));
    btCollisionShape* ball = new btSphereShape(0.2f);
    app.collisionShapes.push_back(ball);
    btVector3 inertia;
    ball->calculateLocalInertia(200, inertia);
    auto* state = new btDefaultMotionState(at(6, 0.6, 7));
    auto* body = new btRigidBody(btRigidBody::btRigidBodyConstructionInfo(200, state, ball, inertia));
    body->setLinearVelocity(btVector3(0, 0, -15));
    app.world->addRigidBody(body);
}

void runScene(HelloWorldApp& app, Plugin& plugin) {
    addShatterBodies(app, plugin);
    app.step(60);
    ASSERT_GT(plugin.lattices().bodies()[0]->pieceCount(), 1) << "the wall should have broken";
    int dented = 0, fractured = 0;
    for (const auto& e : plugin.takeEvents()) {
        dented += e.type == EventType::BodyDented;
        fractured += e.type == EventType::BodyFractured;
    }
    EXPECT_GT(dented, 0) << "the plastic torus should have been dented";
    EXPECT_GT(fractured, 0) << "the chair should have shattered where it landed";
}

TEST(Lifetime, PluginOnTheStackOutlivesHelloWorldsCleanup) {
    HelloWorldApp app;
    Plugin plugin(*app.world); // declared after the world: destroyed after the app's cleanup
    runScene(app, plugin);
    app.deleteObjects();
    EXPECT_FALSE(plugin.attached()); // the watch object went with the app's objects
    EXPECT_TRUE(plugin.bodies().empty());
    app.deleteWorld();
}

TEST(Lifetime, PluginDeletedBeforeTheCleanupLoop) {
    HelloWorldApp app;
    auto plugin = std::make_unique<Plugin>(*app.world);
    runScene(app, *plugin);
    const int appObjects = 3; // ground, sphere, the app's ball
    plugin.reset();
    EXPECT_EQ(app.world->getNumCollisionObjects(), appObjects);
    EXPECT_EQ(app.world->getNumConstraints(), 0);
    app.step(10); // the world works on without Shatter
    app.deleteObjects();
    app.deleteWorld();
}

TEST(Lifetime, PluginDeletedBetweenTheCleanupLoopAndTheWorld) {
    HelloWorldApp app;
    auto plugin = std::make_unique<Plugin>(*app.world);
    runScene(app, *plugin);
    app.deleteObjects();
    plugin.reset();
    app.deleteWorld();
}

TEST(Lifetime, PluginDeletedAfterTheWorld) {
    HelloWorldApp app;
    auto plugin = std::make_unique<Plugin>(*app.world);
    runScene(app, *plugin);
    app.deleteObjects();
    app.deleteWorld();
    plugin.reset();
}

TEST(Lifetime, ConstraintsDeletedFirstAsCommonRigidBodyBaseDoes) {
    HelloWorldApp app;
    Plugin plugin(*app.world);
    runScene(app, plugin);
    ASSERT_FALSE(plugin.joints().empty());
    app.deleteConstraints(); // Shatter's joints among them
    EXPECT_TRUE(plugin.joints().empty());
    app.step(5); // the plugin still runs, without its joints
    app.deleteObjects();
    app.deleteWorld();
}

TEST(Lifetime, WorldDeletedWithShattersBodiesStillInIt) {
    // An application that deletes only what it made itself and then the world: Shatter's
    // objects are still in the world when it goes. The plugin must not call the dead world.
    HelloWorldApp app;
    auto plugin = std::make_unique<Plugin>(*app.world);
    runScene(app, *plugin);
    for (int i = app.world->getNumCollisionObjects() - 1; i >= 0; i--) {
        btCollisionObject* obj = app.world->getCollisionObjectArray()[i];
        btRigidBody* body = btRigidBody::upcast(obj);
        const bool shatters = std::any_of(plugin->bodies().begin(), plugin->bodies().end(),
                                          [&](const auto& b) { return &b->rigidBody() == obj; });
        if (shatters || !body) continue; // Shatter's bodies and its watch object stay
        delete body->getMotionState();
        app.world->removeCollisionObject(obj);
        delete obj;
    }
    app.deleteWorld();
    plugin.reset();
}

TEST(Lifetime, TheApplicationDeletesOneBodyAndTheRestKeepsWorking) {
    HelloWorldApp app;
    Plugin plugin(*app.world);
    runScene(app, plugin);
    VisualBody& fragment = *plugin.lattices().bodies()[0]->pieces().back().body;
    const int bodies = int(plugin.bodies().size());
    btRigidBody* rigid = &fragment.rigidBody();
    delete rigid->getMotionState();
    app.world->removeRigidBody(rigid);
    delete rigid;
    EXPECT_EQ(int(plugin.bodies().size()), bodies - 1);
    bool removed = false;
    for (const auto& e : plugin.takeEvents()) removed = removed || e.type == EventType::BodyRemoved;
    EXPECT_TRUE(removed);
    app.step(30); // the lattice forgot the piece
    EXPECT_TRUE(plugin.attached());
    app.deleteObjects();
    app.deleteWorld();
}

} // namespace
} // namespace shatter
