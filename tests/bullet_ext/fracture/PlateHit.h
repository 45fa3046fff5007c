#pragma once
// A steel plate hit from above by a ball: the scene of the subdivision and ductile-tearing
// tests.
#include <shatter/plugin/geometry/PhysicalMeshBuilder.h>
#include "tests/support/TestWorld.h"

#include <btBulletDynamicsCommon.h>

#include <memory>
#include <vector>

namespace shatter::test {

// An open nx × nz steel sheet of cell h at height 0, facing +y (extruded 1 cm downwards).
inline geometry::PhysicalMesh plate(int nx, int nz, double h) {
    std::vector<Eigen::Vector3d> positions;
    for (int j = 0; j <= nz; ++j)
        for (int i = 0; i <= nx; ++i) positions.push_back({i * h, 0.0, j * h});
    std::vector<std::vector<int>> faces;
    auto v = [&](int i, int j) { return j * (nx + 1) + i; };
    for (int j = 0; j < nz; ++j)
        for (int i = 0; i < nx; ++i) faces.push_back({v(i, j), v(i, j + 1), v(i + 1, j + 1), v(i + 1, j)});
    geometry::PhysicalMeshSettings s;
    s.thickness = 0.01;
    s.density = 7800;
    return geometry::buildPhysicalMesh("plate", positions, faces, s);
}

// A ball of 5 cm radius and `mass` kg falling at 10 m/s onto (0.55, 0.45) of a plate at
// y = 0: it is in the world for `steps` steps, then taken out again.
struct FallingBall {
    btSphereShape shape{0.05f};
    std::unique_ptr<btRigidBody> body;

    void drop(TestWorld& w, float mass, int steps) {
        btVector3 inertia;
        shape.calculateLocalInertia(mass, inertia);
        body = std::make_unique<btRigidBody>(mass, nullptr, &shape, inertia);
        body->setWorldTransform(btTransform(btQuaternion::getIdentity(), btVector3(0.55f, 0.07f, 0.45f)));
        body->setLinearVelocity(btVector3(0, -10, 0));
        w.world.addRigidBody(body.get());
        w.step(steps);
        w.world.removeRigidBody(body.get());
    }
};

} // namespace shatter::test
