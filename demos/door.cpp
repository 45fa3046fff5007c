// shatter-door: the source's Fig. 7. A metal door (a quad mesh) hangs on two hinge joint
// boxes in a static frame; a ball hits it. It swings, and dents where it was hit when the
// impact is faster than the plastic threshold (source 000 §3.5).
#include "demos/OrientedDemo.h"
#include "demos/runner/DemoRunner.h"
#include <shatter/plugin/geometry/PhysicalMesh.h>

#include <iostream>

namespace {

using shatter::demo::ObjText;

// Door 0.9 m × 2.0 m of 5 cm quads facing +z (extruded 1 cm towards −z), frame posts and a
// top beam, and two hinge boxes that overlap the door's left column and the left post.
ObjText doorAndFrame() {
    ObjText obj;
    obj.object("door");
    obj.surface(18, 40, false, false, [](int i, int j) { return Eigen::Vector3d(0.05 * i, 0.02 + 0.05 * j, 0.0); });
    obj.object("frame");
    obj.box({-0.08, 0.0, -0.05}, {0.0, 2.13, 0.05});
    obj.object("frame.right");
    obj.box({0.92, 0.0, -0.05}, {1.0, 2.13, 0.05});
    obj.object("frame.top");
    obj.box({-0.08, 2.05, -0.05}, {1.0, 2.13, 0.05});
    obj.object("joint.hinge.frame.door.low");
    obj.box({-0.02, 0.25, -0.03}, {0.02, 0.45, 0.01});
    obj.object("joint.hinge.frame.door.high");
    obj.box({-0.02, 1.6, -0.03}, {0.02, 1.8, 0.01});
    return obj;
}

} // namespace

int main(int argc, char** argv) {
    shatter::demo::DemoRunner runner("door", "A hinged metal door hit by a ball: it swings and dents where hit.");
    shatter::demo::ThrownBall ball;
    shatter::demo::addBallOptions(runner.cli(), ball);
    shatter::geometry::PhysicalMeshSettings doorMesh;
    doorMesh.thickness = 0.01;
    doorMesh.density = 3000; // a hollow steel door averages about this over its 1 cm
    shatter::BodySettings door;
    door.deformation = shatter::Deformation::Plastic;
    runner.cli().add_option("--plastic-threshold", door.plastic.threshold, "contact speed that dents, m/s")
        ->capture_default_str();
    runner.cli().add_option("--dent-rings", door.plastic.rings, "primitive rings a dent spreads over")
        ->capture_default_str();
    return runner.run(argc, argv, [&](shatter::demo::Scene& scene) {
        scene.addGround();
        const auto object = shatter::geometry::buildPhysicalObject(doorAndFrame().parse("door.obj"), doorMesh);
        for (const auto& w : object.warnings) std::cerr << "shatter-door: warning: " << w << "\n";
        shatter::BodySettings frame;
        frame.dynamic = false;
        const auto added = scene.plugin().addObject(object, door, btTransform::getIdentity(), {{"frame", frame}});
        shatter::VisualBody& body = *added.bodies[0];
        shatter::demo::printWarnings("shatter-door", body);
        shatter::demo::throwBall(scene, ball, btVector3(0.6f, 1.1f, 1.2f), btVector3(0, 0, -1), "ball");
        scene.onFrame([&scene, &body](const shatter::demo::Frame&) { shatter::demo::addDeformationSummary(scene, body); });
    });
}
