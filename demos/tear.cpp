// shatter-tear: a curtain of 50 × 50 quads hangs by ball-joint boxes from a static rail and a
// ball is thrown into it (source 000 §3.6). The curtain is a soft body: it stretches where the
// ball pushes it, and where vertices that share a global id drift more than the tear distance
// apart, the connection between their primitives breaks. By default only the connections
// across the tear line the artist drew (a `tear.curtain` polyline down the middle) may break;
// with --everywhere every connection may. The flood fill over shared global ids opens the
// visual mesh along the broken connections, and the parts become soft bodies of their own
// (curtain.1, curtain.2), each keeping the joints whose boxes it touches. A wall behind stops
// the ball.
#include "demos/OrientedDemo.h"
#include "demos/MeshOptions.h"
#include "demos/TearSummary.h"
#include "demos/runner/DemoRunner.h"
#include <shatter/plugin/common/InputError.h>
#include <shatter/plugin/geometry/PhysicalMesh.h>

#include <iostream>

namespace {

using shatter::demo::ObjText;
using shatter::demo::TearSummary;

// The curtain (x in [−1, 1], y in [0.3, 2.3], facing +z, n × n quads), the rail above it, eight
// ball-joint boxes that overlap the curtain's top row and the rail (none on the tear line, so
// that the line's top is free to open), and the tear line down the middle (x = 0).
ObjText curtainAndRail(int n) {
    ObjText obj;
    obj.object("curtain");
    const double width = 2.0, height = 2.0, bottom = 0.3;
    obj.surface(n, n, false, false, [&](int i, int j) {
        return Eigen::Vector3d(-0.5 * width + width * i / n, bottom + height * j / n, 0.0);
    });
    obj.object("rail");
    obj.box({-1.1, bottom + height + 0.02, -0.03}, {1.1, bottom + height + 0.08, 0.03});
    for (int k = 0; k < 8; ++k) {
        const double x = -0.875 + 0.25 * k;
        obj.object("joint.ball.rail.curtain." + std::to_string(k + 1));
        obj.box({x - 0.03, bottom + height - 0.02, -0.02}, {x + 0.03, bottom + height + 0.04, 0.02});
    }
    obj.object("tear.curtain");
    std::vector<int> line;
    for (int j = 0; j <= n; ++j) line.push_back(1 + j * (n + 1) + n / 2); // the surface's vertex (n/2, j)
    obj.polyline(line);
    return obj;
}

std::string bodyList(const shatter::geometry::PhysicalObject& object) {
    std::string out;
    for (const auto& body : object.bodies) out += (out.empty() ? "" : ", ") + body.name;
    return out;
}

} // namespace

int main(int argc, char** argv) {
    shatter::demo::DemoRunner runner("tear", "A curtain hanging from a rail is hit by a ball and tears along its tear line.");
    shatter::demo::ThrownBall ball;
    ball.speed = 12.0;
    ball.mass = 5.0;
    shatter::demo::addBallOptions(runner.cli(), ball);
    std::string mesh, staticName = "rail";
    int quads = 50;
    runner.cli().add_option("--mesh", mesh, "OBJ file to hang instead of the curtain (its bodies, joint boxes and tear lines)");
    runner.cli().add_option("--static", staticName, "the body of --mesh that is static (the rail)")->capture_default_str();
    runner.cli().add_option("--quads", quads, "the built-in curtain's quads per side")->capture_default_str()->check(CLI::Range(2, 400));
    shatter::geometry::PhysicalMeshSettings meshSettings;
    meshSettings.thickness = 0.01; // Bullet's contact margins need about 1 cm
    meshSettings.density = 150;    // a heavy curtain: 1.5 kg/m²
    shatter::demo::addMeshOptions(runner.cli(), meshSettings);
    shatter::BodySettings cloth;
    cloth.deformation = shatter::Deformation::Soft;
    cloth.solver.stiffness = 0.5;
    cloth.solver.damping = 1.0;
    cloth.tear.enabled = true;
    // 4 mm along the tear line; with --everywhere 15 mm, since at 4 mm the cloth's own weight
    // tears the rows under the joint boxes, where held particles meet free ones.
    double distance = 0.0;
    runner.cli().add_option("--tear-distance", distance,
                            "drift of shared vertices that breaks a connection, m (default 0.004, with --everywhere 0.015)");
    runner.cli().add_flag("--everywhere", cloth.tear.everywhere, "every connection may break, not only the tear lines'");
    runner.cli().add_option("--stiffness", cloth.solver.stiffness, "shape-matching stiffness of the cloth in [0, 1]")
        ->capture_default_str();
    std::unique_ptr<TearSummary> summary;
    return runner.run(argc, argv, [&](shatter::demo::Scene& scene) {
        cloth.tear.distance = runner.cli().count("--tear-distance") ? distance : cloth.tear.everywhere ? 0.015 : 0.004;
        scene.addGround();
        const auto object = shatter::geometry::buildPhysicalObject(
            mesh.empty() ? curtainAndRail(quads).parse("curtain.obj") : shatter::geometry::loadObj(mesh), meshSettings);
        for (const auto& w : object.warnings) std::cerr << "shatter-tear: warning: " << w << "\n";
        if (object.findBody(staticName) < 0)
            throw shatter::InputError("--static: body '" + staticName + "' is not in " +
                                      (mesh.empty() ? std::string("the built-in scene") : mesh) + " (bodies: " +
                                      bodyList(object) + ")");
        shatter::BodySettings rail;
        rail.dynamic = false;
        const auto added = scene.plugin().addObject(object, cloth, btTransform::getIdentity(), {{staticName, rail}});
        summary = std::make_unique<TearSummary>(scene);
        shatter::geometry::Aabb cloths;
        for (shatter::VisualBody* body : added.bodies) {
            shatter::demo::printWarnings("shatter-tear", *body);
            if (body->name() == staticName) continue;
            summary->watch(*body);
            for (const auto& p : body->physicalMesh().primitives) cloths.extend(p.bounds());
        }
        // The ball flies along −z into the middle of the cloth, starting 1 m in front of it.
        const Eigen::Vector3d aim = 0.5 * (cloths.min + cloths.max);
        shatter::demo::throwBall(scene, ball, btVector3(btScalar(aim.x()), btScalar(aim.y()), btScalar(cloths.max.z() + 1.0)),
                                 btVector3(0, 0, -1), "ball");
        // A static wall 1 m behind the cloth stops the ball, so that the pictures stay on the cloth.
        const Eigen::Vector3d half = 0.5 * (cloths.max - cloths.min) + Eigen::Vector3d(0.5, 0.5, 0.0);
        scene.addRigidBody(std::make_unique<btBoxShape>(btVector3(btScalar(half.x()), btScalar(half.y()), 0.05f)), 0.0,
                           btTransform(btQuaternion::getIdentity(),
                                       btVector3(btScalar(aim.x()), btScalar(aim.y()), btScalar(cloths.min.z() - 1.05))),
                           "wall");
        scene.onFrame([&summary](const shatter::demo::Frame& f) { summary->frame(f); });
    });
}
