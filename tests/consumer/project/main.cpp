// The README's "how an app uses it" snippet, compiled and run against the installed package.
#include <shatter/shatter.h>

#include <cstdio>

int main(int argc, char** argv) {
    // The application's own world and loop.
    btDefaultCollisionConfiguration config;
    btCollisionDispatcher dispatcher(&config);
    btDbvtBroadphase broadphase;
    btSequentialImpulseConstraintSolver solver;
    btDiscreteDynamicsWorld world(&dispatcher, &broadphase, &solver, &config);
    world.setGravity(btVector3(0, -9.81f, 0));
    btStaticPlaneShape groundShape(btVector3(0, 1, 0), 0);
    btRigidBody ground(0, nullptr, &groundShape);
    world.addRigidBody(&ground);

    // Shatter: attach, turn a visual mesh into a body, step as usual.
    shatter::Plugin shatter(world);
    const char* path = argc > 1 ? argv[1] : "chair.obj";
    auto object = shatter::geometry::buildPhysicalObject(shatter::geometry::loadObj(path));
    shatter::BodySettings settings;              // density, thickness, friction, ... (SI units)
    auto added = shatter.addObject(object, settings, btTransform(btQuaternion::getIdentity(), btVector3(0, 1, 0)));
    for (int frame = 0; frame < 180; ++frame) {
        world.stepSimulation(1.0f / 60, 4, 1.0f / 240);
        const auto& mesh = added.bodies[0]->visualMesh(); // world-space vertices for the renderer
        (void)mesh;
    }
    for (const shatter::Event& e : shatter.takeEvents()) std::printf("event %s %s\n", shatter::toString(e.type), e.name.c_str());
    const btVector3 v = added.bodies[0]->rigidBody().getLinearVelocity();
    std::printf("primitives %zu, speed after 3 s %.4f m/s\n", added.bodies[0]->physicalMesh().primitives.size(), double(v.length()));
    world.removeRigidBody(&ground);
    return v.length() < 0.05f ? 0 : 1; // it must have come to rest on the ground
}
