#pragma once
// A plain Bullet world as an application would set it up, for tests.
#include <btBulletDynamicsCommon.h>

#include <memory>

namespace shatter::test {

// A transform with no rotation that places a body at (x, y, z).
inline btTransform at(double x, double y, double z) {
    return btTransform(btQuaternion::getIdentity(), btVector3(btScalar(x), btScalar(y), btScalar(z)));
}

struct TestWorld {
    btDefaultCollisionConfiguration config;
    btCollisionDispatcher dispatcher{&config};
    btDbvtBroadphase broadphase;
    btSequentialImpulseConstraintSolver solver;
    btDiscreteDynamicsWorld world{&dispatcher, &broadphase, &solver, &config};
    btStaticPlaneShape groundShape{btVector3(0, 1, 0), 0};
    std::unique_ptr<btRigidBody> ground;

    TestWorld() { world.setGravity(btVector3(0, -9.81f, 0)); }
    ~TestWorld() {
        if (ground) world.removeRigidBody(ground.get());
    }
    void addGround(double friction = 0.6) {
        ground = std::make_unique<btRigidBody>(0, nullptr, &groundShape);
        ground->setFriction(btScalar(friction));
        world.addRigidBody(ground.get());
    }
    // n internal steps of 1/240 s.
    void step(int n) {
        for (int i = 0; i < n; ++i) world.stepSimulation(1.0f / 240, 1, 1.0f / 240);
    }
};

} // namespace shatter::test
