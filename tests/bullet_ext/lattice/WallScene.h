#pragma once
// A small anchored wall (8 × 6 × 2 cells, 576 tets) in a world with a ground, and a ball flying
// at its face: the Bullet-side lattice tests' scene.
#include <shatter/bullet_ext/lattice/LatticeBody.h>
#include <shatter/bullet_ext/Plugin.h>
#include <shatter/plugin/lattice/TetGenerators.h>
#include "tests/support/TestWorld.h"

#include <cstdint>
#include <memory>

namespace shatter::test {

struct WallScene {
    TestWorld w;
    Plugin plugin{w.world};
    LatticeBody* wall = nullptr;
    btSphereShape ballShape{0.15f};
    std::unique_ptr<btRigidBody> ball;

    explicit WallScene(double speed, std::uint64_t seed = 1, double ballMass = 60.0, const DebrisSettings& debris = {},
                       int fragmentBudget = 0, bool keepPairsOnShrink = false) {
        w.addGround();
        lattice::GeneratorOptions g;
        g.jitter = 0.15;
        g.seed = seed;
        const lattice::TetMesh mesh = lattice::tetBox({0.8, 0.6, 0.2}, {8, 6, 2}, g);
        LatticeSettings s;
        s.name = "wall";
        s.seed = seed;
        s.debris = debris;
        s.fragmentBudget = fragmentBudget;
        s.keepPairsOnShrink = keepPairsOnShrink;
        s.fixedTets = lattice::tetsWithFaceOnPlane(mesh, {0, 1, 0}, -0.3, 1e-9);
        wall = &plugin.addLatticeBody(mesh, s, btTransform(btQuaternion::getIdentity(), btVector3(0, 0.3f, 0)));
        btVector3 inertia;
        ballShape.calculateLocalInertia(btScalar(ballMass), inertia);
        ball = std::make_unique<btRigidBody>(btScalar(ballMass), nullptr, &ballShape, inertia);
        ball->setWorldTransform(btTransform(btQuaternion::getIdentity(), btVector3(0, 0.3f, 0.4f)));
        ball->setLinearVelocity(btVector3(0, 0, btScalar(-speed)));
        w.world.addRigidBody(ball.get());
    }
    ~WallScene() { w.world.removeRigidBody(ball.get()); }
};

} // namespace shatter::test
