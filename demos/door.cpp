// shatter-door: the source's Fig. 7. A metal door (a quad mesh) hangs on two hinge joint
// boxes in a static frame; a ball hits it. It swings, and dents where it was hit when the
// impact is faster than the plastic threshold (source 000 §3.5). With --subdivide the door is
// coarse (30 cm × 25 cm quads) and its fracture mode is Subdivide: the hit cuts the quads near
// it finer, the door stays one body, and the dent is made on the fine pieces (000 §3.6).
// --tear is the source's ductile fracture (000 §3.6): the coarse door subdivides, dents and
// may tear wherever a dent moved neighbouring pieces apart by more than the tear distance. A
// hard hit next to the lower hinge bends the door there against the pieces the hinge box
// holds, and tears it off that hinge: the held pieces stay on the lower hinge as a torn-off
// scrap (door.1), the door (door.2) hangs on the upper hinge.
#include "demos/OrientedDemo.h"
#include "demos/TearSummary.h"
#include "demos/runner/DemoRunner.h"
#include <shatter/bullet_ext/Joints.h>
#include <shatter/plugin/geometry/PhysicalMesh.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <memory>

namespace {

using shatter::demo::ObjText;

// Door 0.9 m × 2.0 m of quads between the columns `xs` and rows `ys` (m), facing +z (extruded
// 1 cm towards −z), frame posts and a top beam, and two hinge boxes that overlap the door's
// left column and the left post, 20 cm tall less `inset` at each end.
ObjText doorAndFrame(const std::vector<double>& xs, const std::vector<double>& ys, double inset = 0.0) {
    ObjText obj;
    obj.object("door");
    obj.surface(int(xs.size()) - 1, int(ys.size()) - 1, false, false,
                [&](int i, int j) { return Eigen::Vector3d(xs[size_t(i)], ys[size_t(j)], 0.0); });
    obj.object("frame");
    obj.box({-0.08, 0.0, -0.05}, {0.0, 2.13, 0.05});
    obj.object("frame.right");
    obj.box({0.92, 0.0, -0.05}, {1.0, 2.13, 0.05});
    obj.object("frame.top");
    obj.box({-0.08, 2.05, -0.05}, {1.0, 2.13, 0.05});
    obj.object("joint.hinge.frame.door.low");
    obj.box({-0.02, 0.25 + inset, -0.03}, {0.02, 0.45 - inset, 0.01});
    obj.object("joint.hinge.frame.door.high");
    obj.box({-0.02, 1.6 + inset, -0.03}, {0.02, 1.8 - inset, 0.01});
    return obj;
}

// n + 1 evenly spaced values from `from` to `to`.
std::vector<double> evenly(int n, double from, double to) {
    std::vector<double> out;
    for (int i = 0; i <= n; ++i) out.push_back(from + (to - from) * i / n);
    return out;
}

// The door for --tear: a hinge leaf, a 4 cm column whose quads end 2 cm beyond the hinge
// boxes, so that a hinge holds a leaf of 4 × 20 cm (the primitives a joint box touches are
// fixed), then three coarse columns.
ObjText tearingDoorAndFrame() {
    return doorAndFrame({0.0, 0.04, 0.3, 0.6, 0.9}, {0.02, 0.25, 0.45, 0.7, 0.95, 1.2, 1.4, 1.6, 1.8, 2.02}, 0.02);
}

// The deepest point of the watched bodies' rest shapes behind the door's back face (z = −1 cm):
// how far the dents pushed the door in, also across tears (a torn part starts its own
// VisualBody::dentDepthMax from zero).
double dentBehindDoor(const std::vector<const shatter::VisualBody*>& bodies) {
    double deepest = 0.0;
    for (const shatter::VisualBody* body : bodies)
        for (const auto& primitive : body->physicalMesh().primitives)
            for (const auto& v : primitive.vertices()) deepest = std::max(deepest, -0.01 - v.z());
    return deepest;
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
    bool subdivide = false, tear = false;
    runner.cli().add_flag("--subdivide", subdivide,
                          "coarse door (3 x 8 quads) cut finer where hit (fracture mode Subdivide), dented there");
    runner.cli().add_flag("--tear", tear,
                          "ductile fracture: --subdivide, and the door tears where a dent moved pieces apart; "
                          "a ram (the ball's mass and speed, 20 m/s unless given) hits it next to the lower hinge");
    door.fracture.mode = shatter::FractureMode::Subdivide;
    door.fracture.pattern = shatter::PatternKind::Voronoi;
    door.fracture.setCells(96);
    door.fracture.radius = 0.2;
    door.fracture.threshold = 5.0; // N·s: the ball brings 50
    runner.cli().add_option("--subdivide-radius", door.fracture.radius, "cells within this distance (m) of the hit cut")
        ->capture_default_str();
    door.tear.everywhere = true;
    door.tear.distance = 0.005; // half the door's thickness
    runner.cli().add_option("--tear-distance", door.tear.distance,
                            "with --tear: drift of shared vertices that breaks a connection, m")
        ->capture_default_str();
    std::unique_ptr<shatter::demo::TearSummary> torn;
    return runner.run(argc, argv, [&](shatter::demo::Scene& scene) {
        scene.addGround();
        door.fracture.enabled = subdivide || tear;
        door.fracture.seed = scene.seed();
        door.tear.enabled = tear;
        if (tear && !runner.cli().count("--ball-speed")) ball.speed = 20.0;
        const auto object = shatter::geometry::buildPhysicalObject(
            (tear        ? tearingDoorAndFrame()
             : subdivide ? doorAndFrame(evenly(3, 0.0, 0.9), evenly(8, 0.02, 2.02))
                         : doorAndFrame(evenly(18, 0.0, 0.9), evenly(40, 0.02, 2.02))).parse("door.obj"), doorMesh);
        for (const auto& w : object.warnings) std::cerr << "shatter-door: warning: " << w << "\n";
        shatter::BodySettings frame;
        frame.dynamic = false;
        const auto added = scene.plugin().addObject(object, door, btTransform::getIdentity(), {{"frame", frame}});
        shatter::VisualBody& body = *added.bodies[0];
        shatter::demo::printWarnings("shatter-door", body);
        // Where the ball meets the door: its middle. With --tear a ram, a box 12 × 40 cm
        // across, hits the door flat next to the lower hinge's leaf (x 0-4 cm, y 0.25-0.45 m)
        // and overlapping it, so that it pushes in every piece around the leaf: a ball touches
        // the door at a point and punches out only the piece there.
        const Eigen::Vector3d aim = tear ? Eigen::Vector3d(0.08, 0.35, 0.0) : Eigen::Vector3d(0.6, 1.1, 0.0);
        const btVector3 from(btScalar(aim.x()), btScalar(aim.y()), tear ? 0.3f : 1.2f);
        if (tear) {
            btRigidBody& ram = scene.addRigidBody(std::make_unique<btBoxShape>(btVector3(0.06f, 0.2f, 0.05f)), ball.mass,
                                                  btTransform(btQuaternion::getIdentity(), from), "ram");
            ram.setLinearVelocity(btVector3(0, 0, -btScalar(ball.speed)));
        } else {
            shatter::demo::throwBall(scene, ball, from, btVector3(0, 0, -1), "ball");
        }
        const int primitivesBefore = body.shape().primitiveCount();
        const double massInitial = body.physicalMesh().mass.mass;
        if (tear) {
            torn = std::make_unique<shatter::demo::TearSummary>(scene);
            torn->watch(body);
        }
        auto subdivisions = std::make_shared<int>(0), subdividedAt = std::make_shared<int>(0);
        auto deepest = std::make_shared<double>(0.0);
        scene.onFrame([&scene, &body, &torn, primitivesBefore, massInitial, subdivisions, subdividedAt, deepest,
                       aim](const shatter::demo::Frame& frame) {
            for (const auto& e : frame.events) {
                if (e.type != shatter::EventType::BodySubdivided) continue;
                if (++*subdivisions == 1) *subdividedAt = frame.index;
            }
            scene.addSummary("subdivision_events", *subdivisions);
            scene.addSummary("primitives_before", primitivesBefore);
            if (torn) {
                // The door may be gone (torn into parts): the summary is over its parts.
                torn->frame(frame);
                const auto parts = torn->watched();
                int primitives = 0;
                for (const shatter::VisualBody* part : parts) primitives += part->shape().primitiveCount();
                *deepest = std::max(*deepest, dentBehindDoor(parts));
                scene.addSummary("primitives", primitives);
                scene.addSummary("dent_depth_max", *deepest);
                // Which of the door's parts each hinge holds now (a torn part keeps a copy of
                // every joint whose box it touches).
                nlohmann::json hinges = nlohmann::json::object();
                for (const auto& joint : scene.plugin().joints())
                    if (!joint->broken()) hinges[joint->name()].push_back(joint->bodyB().name());
                scene.addSummary("hinges", hinges);
                return;
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
            scene.addSummary("mass_initial", massInitial);
            scene.addSummary("mass_final", body.physicalMesh().mass.mass);
            scene.addSummary("mass_error_relative", std::abs(body.physicalMesh().mass.mass - massInitial) / massInitial);
        });
    });
}
