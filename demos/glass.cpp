// shatter-glass: a pane of glass hangs in a frame on two hinge joint boxes and a ball hits it
// off-centre. A glass pattern (radial sectors times rings) is placed at the hit: a hole and
// radial shards break free, and the rest of the pane stays on its hinges, which are handed on
// to the piece that holds them (source 000 §3.6, last paragraph).
#include "demos/FractureDemo.h"
#include "demos/OrientedDemo.h"
#include "demos/runner/DemoRunner.h"
#include <shatter/plugin/geometry/PhysicalMesh.h>

#include <iostream>

namespace {

using shatter::demo::ObjText;

// A pane 0.8 m × 0.6 m of 5 cm quads facing +z (extruded 6 mm towards −z), 2 cm above the
// frame's sill; frame posts, sill and top beam; hinge boxes over the pane's left column and
// the left post.
ObjText paneAndFrame() {
    ObjText obj;
    obj.object("pane");
    obj.surface(16, 12, false, false, [](int i, int j) { return Eigen::Vector3d(0.05 * i, 0.52 + 0.05 * j, 0.0); });
    obj.object("frame");
    obj.box({-0.06, 0.44, -0.03}, {0.0, 1.18, 0.03});
    obj.object("frame.right");
    obj.box({0.82, 0.44, -0.03}, {0.88, 1.18, 0.03});
    obj.object("frame.sill");
    obj.box({-0.06, 0.44, -0.03}, {0.88, 0.5, 0.03});
    obj.object("frame.top");
    obj.box({-0.06, 1.14, -0.03}, {0.88, 1.18, 0.03});
    obj.object("joint.hinge.frame.pane.low");
    obj.box({-0.02, 0.6, -0.02}, {0.02, 0.72, 0.01});
    obj.object("joint.hinge.frame.pane.high");
    obj.box({-0.02, 0.92, -0.02}, {0.02, 1.04, 0.01});
    return obj;
}

} // namespace

int main(int argc, char** argv) {
    shatter::demo::DemoRunner runner("glass", "A pane of glass on two hinges, hit off-centre by a ball, shatters around the hit.");
    shatter::demo::ThrownBall ball;
    ball.speed = 8.0;
    ball.mass = 0.4;
    ball.radius = 0.05;
    shatter::demo::addBallOptions(runner.cli(), ball);
    std::string mesh;
    runner.cli().add_option("--mesh", mesh, "OBJ file to hang in place of the pane (its first body is hit)");
    shatter::geometry::PhysicalMeshSettings paneMesh;
    paneMesh.thickness = 0.006;
    paneMesh.density = 2500; // soda-lime glass
    shatter::BodySettings pane;
    pane.fracture.pattern = shatter::PatternKind::Glass;
    pane.fracture.cells = 64;
    pane.fracture.threshold = 1.0; // N·s: the ball (0.4 kg at 8 m/s) gives about 3
    pane.fracture.radius = 0.25;
    pane.fracture.depth = 0;
    shatter::demo::addFractureOptions(runner.cli(), pane.fracture);
    std::unique_ptr<shatter::demo::FractureSummary> summary;
    return runner.run(argc, argv, [&](shatter::demo::Scene& scene) {
        scene.addGround();
        pane.fracture.seed = scene.seed();
        summary = std::make_unique<shatter::demo::FractureSummary>(scene);
        const auto file = mesh.empty() ? paneAndFrame().parse("glass.obj") : shatter::geometry::loadObj(mesh);
        const auto object = shatter::geometry::buildPhysicalObject(file, paneMesh);
        for (const auto& w : object.warnings) std::cerr << "shatter-glass: warning: " << w << "\n";
        shatter::BodySettings frame;
        frame.dynamic = false;
        const auto added = scene.plugin().addObject(object, pane, btTransform::getIdentity(), {{"frame", frame}});
        summary->watch(*added.bodies[0]);
        shatter::demo::throwBall(scene, ball, btVector3(0.58f, 0.9f, 0.6f), btVector3(0, 0, -1), "ball");
        scene.onFrame([&summary](const shatter::demo::Frame& f) { summary->frame(f); });
    });
}
