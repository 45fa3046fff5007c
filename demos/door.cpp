// shatter-door: the source's Fig. 7. A metal door (a quad mesh) hangs on two hinge joint
// boxes in a static frame; a ball hits it. It swings, and dents where it was hit when the
// impact is faster than the plastic threshold (source 000 §3.5). With --subdivide the door is
// coarse (30 cm × 25 cm quads) and its fracture mode is Subdivide: the hit cuts the quads near
// it finer, the door stays one body, and the dent is made on the fine pieces (000 §3.6).
#include "demos/OrientedDemo.h"
#include "demos/runner/DemoRunner.h"
#include <shatter/plugin/geometry/PhysicalMesh.h>

#include <cmath>
#include <iostream>
#include <memory>

namespace {

using shatter::demo::ObjText;

// Door 0.9 m × 2.0 m of columns × rows quads facing +z (extruded 1 cm towards −z), frame
// posts and a top beam, and two hinge boxes that overlap the door's left column and the left post.
ObjText doorAndFrame(int columns, int rows) {
    ObjText obj;
    obj.object("door");
    obj.surface(columns, rows, false, false,
                [&](int i, int j) { return Eigen::Vector3d(0.9 * i / columns, 0.02 + 2.0 * j / rows, 0.0); });
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
    bool subdivide = false;
    runner.cli().add_flag("--subdivide", subdivide,
                          "coarse door (3 x 8 quads) cut finer where hit (fracture mode Subdivide), dented there");
    door.fracture.mode = shatter::FractureMode::Subdivide;
    door.fracture.pattern = shatter::PatternKind::Voronoi;
    door.fracture.setCells(96);
    door.fracture.radius = 0.2;
    door.fracture.threshold = 5.0; // N·s: the ball brings 50
    runner.cli().add_option("--subdivide-radius", door.fracture.radius, "cells within this distance (m) of the hit cut")
        ->capture_default_str();
    return runner.run(argc, argv, [&](shatter::demo::Scene& scene) {
        scene.addGround();
        door.fracture.enabled = subdivide;
        door.fracture.seed = scene.seed();
        const auto object = shatter::geometry::buildPhysicalObject(
            (subdivide ? doorAndFrame(3, 8) : doorAndFrame(18, 40)).parse("door.obj"), doorMesh);
        for (const auto& w : object.warnings) std::cerr << "shatter-door: warning: " << w << "\n";
        shatter::BodySettings frame;
        frame.dynamic = false;
        const auto added = scene.plugin().addObject(object, door, btTransform::getIdentity(), {{"frame", frame}});
        shatter::VisualBody& body = *added.bodies[0];
        shatter::demo::printWarnings("shatter-door", body);
        const Eigen::Vector3d aim(0.6, 1.1, 0.0); // where the ball meets the door
        shatter::demo::throwBall(scene, ball, btVector3(btScalar(aim.x()), btScalar(aim.y()), 1.2f), btVector3(0, 0, -1), "ball");
        const int primitivesBefore = body.shape().primitiveCount();
        const double massInitial = body.physicalMesh().mass.mass;
        auto subdivisions = std::make_shared<int>(0), subdividedAt = std::make_shared<int>(0);
        scene.onFrame([&scene, &body, primitivesBefore, massInitial, subdivisions, subdividedAt, aim](const shatter::demo::Frame& frame) {
            for (const auto& e : frame.events) {
                if (e.type != shatter::EventType::BodySubdivided) continue;
                if (++*subdivisions == 1) *subdividedAt = frame.index;
            }
            // A close-up of the dent half a second after the first subdivision: the door's
            // surface within 50 cm of where the ball was aimed (rest coordinates = the door's
            // start pose), seen from the usual direction.
            if (*subdividedAt > 0 && frame.index == *subdividedAt + 30) {
                const auto& rest = body.physicalMesh().visual.positions;
                const auto& now = body.visualMesh().positions;
                std::vector<Eigen::Vector3d> near;
                for (size_t i = 0; i < rest.size(); ++i)
                    if ((rest[i] - aim).norm() < 0.5) near.push_back(now[i]);
                scene.pictureAfterFrame("dent.png", near);
            }
            shatter::demo::addDeformationSummary(scene, body);
            scene.addSummary("subdivision_events", *subdivisions);
            scene.addSummary("primitives_before", primitivesBefore);
            scene.addSummary("mass_initial", massInitial);
            scene.addSummary("mass_final", body.physicalMesh().mass.mass);
            scene.addSummary("mass_error_relative", std::abs(body.physicalMesh().mass.mass - massInitial) / massInitial);
        });
    });
}
