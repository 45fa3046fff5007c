#pragma once
// shatter-tear's scene, shared by the demo and its benchmark (shatter-bench-tear): a soft
// cloth (the built-in curtain of quads × quads, or the bodies of an OBJ file) hanging by
// ball-joint boxes from a static body, a ball thrown into the middle of the cloth along −z,
// and a static wall 1 m behind it that stops the ball.
#include "demos/OrientedDemo.h"
#include <shatter/plugin/common/InputError.h>
#include <shatter/plugin/geometry/PhysicalMesh.h>

#include <iostream>
#include <string>
#include <vector>

namespace shatter::demo {

struct TearCurtain {
    int quads = 50;           // the built-in curtain's quads per side
    std::string mesh;         // an OBJ file to hang instead (empty: the built-in curtain)
    std::string staticName = "rail";
    geometry::PhysicalMeshSettings meshSettings;
    BodySettings cloth;
    ThrownBall ball;

    TearCurtain() {
        meshSettings.thickness = 0.01; // Bullet's contact margins need about 1 cm
        meshSettings.density = 150;    // a heavy curtain: 1.5 kg/m²
        cloth.deformation = Deformation::Soft;
        cloth.solver.stiffness = 0.5;
        cloth.solver.damping = 1.0;
        cloth.tear.enabled = true;
        cloth.tear.distance = 0.004;
        ball.speed = 12.0;
        ball.mass = 5.0;
    }
};

// The curtain (x in [−1, 1], y in [0.3, 2.3], facing +z, n × n quads), the rail above it, eight
// ball-joint boxes that overlap the curtain's top row and the rail (none on the tear line, so
// that the line's top is free to open), and the tear line down the middle (x = 0).
inline ObjText curtainAndRail(int n) {
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

// Builds the scene; returns the cloth bodies (every body but the static one). Throws
// shatter::InputError when the static body is not in the mesh.
inline std::vector<VisualBody*> buildTearCurtain(Scene& scene, const TearCurtain& c, const std::string& program) {
    scene.addGround();
    const auto object =
        geometry::buildPhysicalObject(c.mesh.empty() ? curtainAndRail(c.quads).parse("curtain.obj") : geometry::loadObj(c.mesh),
                                      c.meshSettings);
    for (const auto& w : object.warnings) std::cerr << program << ": warning: " << w << "\n";
    if (object.findBody(c.staticName) < 0) {
        std::string bodies;
        for (const auto& body : object.bodies) bodies += (bodies.empty() ? "" : ", ") + body.name;
        throw InputError("--static: body '" + c.staticName + "' is not in " +
                         (c.mesh.empty() ? std::string("the built-in scene") : c.mesh) + " (bodies: " + bodies + ")");
    }
    BodySettings rail;
    rail.dynamic = false;
    const auto added = scene.plugin().addObject(object, c.cloth, btTransform::getIdentity(), {{c.staticName, rail}});
    std::vector<VisualBody*> cloths;
    geometry::Aabb box;
    for (VisualBody* body : added.bodies) {
        printWarnings(program, *body);
        if (body->name() == c.staticName) continue;
        cloths.push_back(body);
        for (const auto& p : body->physicalMesh().primitives) box.extend(p.bounds());
    }
    // The ball flies along −z into the middle of the cloth, starting 1 m in front of it.
    const Eigen::Vector3d aim = 0.5 * (box.min + box.max);
    throwBall(scene, c.ball, btVector3(btScalar(aim.x()), btScalar(aim.y()), btScalar(box.max.z() + 1.0)),
              btVector3(0, 0, -1), "ball");
    // A static wall 1 m behind the cloth stops the ball, so that the pictures stay on the cloth.
    const Eigen::Vector3d half = 0.5 * (box.max - box.min) + Eigen::Vector3d(0.5, 0.5, 0.0);
    scene.addRigidBody(std::make_unique<btBoxShape>(btVector3(btScalar(half.x()), btScalar(half.y()), 0.05f)), 0.0,
                       btTransform(btQuaternion::getIdentity(),
                                   btVector3(btScalar(aim.x()), btScalar(aim.y()), btScalar(box.min.z() - 1.05))),
                       "wall");
    return cloths;
}

} // namespace shatter::demo
