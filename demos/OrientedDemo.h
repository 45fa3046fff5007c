#pragma once
// What the oriented-particle demos (door, soft, car) and their benchmark share: meshes
// generated as OBJ text (so they go through the same loader and physical-mesh rules as a
// user's file), the ball they throw, and the summary keys.
#include "demos/runner/Scene.h"
#include <shatter/plugin/geometry/ObjFile.h>
#include <shatter/plugin/geometry/PhysicalMesh.h>

#include <BulletCollision/CollisionShapes/btBoxShape.h>
#include <BulletCollision/CollisionShapes/btSphereShape.h>
#include <CLI/CLI.hpp>
#include <Eigen/Core>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <random>
#include <string>
#include <vector>

namespace shatter::demo {

// An OBJ file being written: objects, vertices (1-based ids returned) and polygon faces.
class ObjText {
public:
    void object(const std::string& name) { text_ += "o " + name + "\n"; }
    int vertex(const Eigen::Vector3d& p) {
        char line[96];
        std::snprintf(line, sizeof line, "v %.9g %.9g %.9g\n", p.x(), p.y(), p.z());
        text_ += line;
        return ++vertices_;
    }
    void face(std::initializer_list<int> ids) {
        text_ += "f";
        for (int id : ids) {
            text_ += ' ';
            text_ += std::to_string(id); // appended apart: GCC 12 warns falsely (-Wrestrict) on " " + s
        }
        text_ += "\n";
    }
    void polygon(const std::vector<int>& ids) {
        text_ += "f";
        for (int id : ids) {
            text_ += ' ';
            text_ += std::to_string(id);
        }
        text_ += "\n";
    }
    // A polyline (`l`) over vertex ids: a tear line in a `tear.<body>` object.
    void polyline(const std::vector<int>& ids) {
        text_ += "l";
        for (int id : ids) {
            text_ += ' ';
            text_ += std::to_string(id);
        }
        text_ += "\n";
    }
    // A closed box between two corners.
    void box(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
        int v[8];
        for (int c = 0; c < 8; ++c) v[c] = vertex({c & 1 ? hi.x() : lo.x(), c & 2 ? hi.y() : lo.y(), c & 4 ? hi.z() : lo.z()});
        face({v[0], v[2], v[3], v[1]});
        face({v[4], v[5], v[7], v[6]});
        face({v[0], v[1], v[5], v[4]});
        face({v[2], v[6], v[7], v[3]});
        face({v[0], v[4], v[6], v[2]});
        face({v[1], v[3], v[7], v[5]});
    }
    // A quad surface over a grid of points point(i, j), i < nu, j < nv, wrapped in u and/or
    // v (else one more row or column); quads are wound so that d/du × d/dv is their outward
    // side.
    template <class Point>
    void surface(int nu, int nv, bool closedU, bool closedV, const Point& point) {
        const int columns = closedU ? nu : nu + 1, rows = closedV ? nv : nv + 1;
        const int first = vertices_ + 1;
        for (int j = 0; j < rows; ++j)
            for (int i = 0; i < columns; ++i) vertex(point(i, j));
        auto id = [&](int i, int j) { return first + (j % rows) * columns + (i % columns); };
        for (int j = 0; j < nv; ++j)
            for (int i = 0; i < nu; ++i) face({id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
    }
    geometry::ObjFile parse(const std::string& name) const { return geometry::parseObj(text_, name); }

private:
    std::string text_;
    int vertices_ = 0;
};

// The ball the door and car demos throw (--ball-speed, --ball-mass).
struct ThrownBall {
    double speed = 10.0; // m/s
    double mass = 5.0;   // kg
    double radius = 0.12; // m
};

inline void addBallOptions(CLI::App& cli, ThrownBall& ball) {
    cli.add_option("--ball-speed", ball.speed, "ball speed in m/s")->capture_default_str()->check(CLI::NonNegativeNumber);
    cli.add_option("--ball-mass", ball.mass, "ball mass in kg")->capture_default_str()->check(CLI::PositiveNumber);
}

inline btRigidBody& throwBall(Scene& scene, const ThrownBall& ball, const btVector3& from, const btVector3& direction,
                              const std::string& name) {
    btRigidBody& body = scene.addRigidBody(std::make_unique<btSphereShape>(btScalar(ball.radius)), ball.mass,
                                           btTransform(btQuaternion::getIdentity(), from), name);
    body.setLinearVelocity(direction.normalized() * btScalar(ball.speed));
    return body;
}

// A car-like shell: a superellipsoid 4.2 m × 1.4 m × 1.8 m (x long, y up) of nu × nv quads,
// open at the two poles (small holes under the roof and floor), resting on y = 0.
inline ObjText carShell(int nu = 200, int nv = 80) {
    ObjText obj;
    obj.object("car");
    const Eigen::Vector3d half(2.1, 0.7, 0.9);
    const double e = 0.35; // < 1: boxy
    auto signedPow = [](double x, double p) { return std::copysign(std::pow(std::abs(x), p), x); };
    const double polar = 1.45; // latitude range ±polar rad, leaves the poles open
    obj.surface(nu, nv, true, false, [&](int i, int j) {
        const double u = 2.0 * M_PI * i / nu, v = -polar + 2.0 * polar * j / nv;
        const double cv = signedPow(std::cos(v), e), sv = signedPow(std::sin(v), e);
        return Eigen::Vector3d(half.x() * cv * signedPow(std::cos(u), e), half.y() * (1.0 + sv) + 0.3,
                               -half.z() * cv * signedPow(std::sin(u), e));
    });
    return obj;
}

// A torus (a tyre) of radii R (to the tube's centre) and r (the tube), axis y, centred at c.
inline void torus(ObjText& obj, double R, double r, int nu, int nv, const Eigen::Vector3d& c) {
    obj.surface(nu, nv, true, true, [&](int i, int j) {
        const double u = 2.0 * M_PI * i / nu, v = 2.0 * M_PI * j / nv;
        const double ring = R + r * std::cos(v);
        return Eigen::Vector3d(c.x() + ring * std::cos(u), c.y() + r * std::sin(v), c.z() - ring * std::sin(u));
    });
}

// Prints a body's warnings (e.g. a primitive graph in several parts) as the demos do.
inline void printWarnings(const std::string& program, const VisualBody& body) {
    for (const auto& w : body.warnings()) std::cerr << program << ": warning: " << w << "\n";
}

// The summary keys every oriented-particle demo writes for its deformable body.
inline void addDeformationSummary(Scene& scene, const VisualBody& body) {
    scene.addSummary("primitives", body.shape().primitiveCount());
    scene.addSummary("dent_depth_max", body.dentDepthMax());
    scene.addSummary("plastic_events", body.plasticEvents());
}

// n³ closed cubes of side h, each inset by 0.1 µm so that neighbours share no vertex (shared
// vertices would weld them into one part); they still touch within the contact tolerance.
inline ObjText cubeJelly(int n, double h, const Eigen::Vector3d& corner) {
    ObjText obj;
    for (int k = 0; k < n; ++k)
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                obj.object("jelly." + std::to_string((k * n + j) * n + i));
                const Eigen::Vector3d lo = corner + h * Eigen::Vector3d(i, j, k);
                obj.box(lo + Eigen::Vector3d::Constant(1e-7), lo + Eigen::Vector3d::Constant(h - 1e-7));
            }
    return obj;
}

inline Eigen::Vector3d centreOfMass(const oriented::OrientedParticles& p) {
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    double m = 0.0;
    for (int i = 0; i < p.size(); ++i) c += p.mass[i] * p.position[i], m += p.mass[i];
    return c / m;
}

inline double highestPoint(const oriented::OrientedParticles& p) {
    double y = -1e300;
    for (const auto& x : p.position) y = std::max(y, x.y());
    return y;
}

// shatter-soft's two soft bodies: a jelly of 5³ cubes (4 cm) and a tyre of 432 extruded quads.
struct SoftScene {
    BodySettings jelly = [] {
        BodySettings s;
        s.deformation = Deformation::Soft;
        s.solver.stiffness = 0.005; // per sweep: 4 sweeps at 240 Hz still hold it; lower wobbles more
        s.solver.damping = 1.0;
        s.solver.sleepSpeed = 0.01; // m/s: both sleep half a second after coming to rest
        return s;
    }();
    BodySettings tyre = [] {
        BodySettings s;
        s.deformation = Deformation::Soft;
        s.solver.stiffness = 0.2;
        s.solver.sleepSpeed = 0.01; // lies still from about 1.2 s, asleep from 1.7 s
        return s;
    }();
    double ballMass = 2.0;  // kg, dropped on the jelly at 2 s
    double boxMass = 40.0;  // kg, slid into the jelly at 0.5 s
    double boxSpeed = 2.0;  // m/s
};

// shatter-soft's scene: the ground, the jelly (dropped from 0.3 m), the tilted tyre, a box
// slid into the jelly at 0.5 s and a ball dropped on it at 2 s; the summary gets how far the
// box shoved the jelly, how deep the ball sank in and how high it bounced back.
inline void buildSoftScene(Scene& scene, const SoftScene& soft) {
    scene.addGround();
    const auto jellyMesh = geometry::buildPhysicalObject(cubeJelly(5, 0.04, {-0.6, 0.3, -0.1}).parse("jelly.obj"), {});
    ObjText tyreObj;
    tyreObj.object("tyre");
    torus(tyreObj, 0.3, 0.1, 36, 12, {0.5, 0.5, 0.0});
    geometry::PhysicalMeshSettings tyreMesh;
    tyreMesh.thickness = 0.02;
    tyreMesh.fill = geometry::Fill::Shell; // an inflated tyre is hollow: its closed torus is not solid rubber
    const auto tyreObject = geometry::buildPhysicalObject(tyreObj.parse("tyre.obj"), tyreMesh);
    VisualBody& j = scene.plugin().addVisualBody(jellyMesh.bodies[0], soft.jelly, btTransform::getIdentity());
    const btTransform tilt(btQuaternion(btVector3(0, 0, 1), 0.3f));
    VisualBody& t = scene.plugin().addVisualBody(tyreObject.bodies[0], soft.tyre, tilt);
    printWarnings("shatter-soft", j);
    printWarnings("shatter-soft", t);
    // The box waits on the ground left of the jelly and the ball above it, held still
    // until their moment: the box is launched at 0.5 s, the ball let go at 2 s.
    btRigidBody& box = scene.addRigidBody(std::make_unique<btBoxShape>(btVector3(0.1f, 0.1f, 0.1f)), soft.boxMass,
                                          btTransform(btQuaternion::getIdentity(), btVector3(-0.95f, 0.1f, 0.0f)), "box");
    btRigidBody& ball = scene.addRigidBody(std::make_unique<btSphereShape>(btScalar(0.05)), soft.ballMass,
                                           btTransform(btQuaternion::getIdentity(), btVector3(-0.3f, 0.75f, 0.0f)), "ball");
    for (btRigidBody* b : {&ball, &box}) b->setActivationState(DISABLE_SIMULATION);
    struct Watch {
        double jellyTop = 0.0, ballLowest = 1e300, ballRebound = -1e300, jellyXBeforeBox = 0.0;
        int phase = 0;
    };
    auto watch = std::make_shared<Watch>();
    scene.onFrame([&scene, &j, &t, &ball, &box, watch, boxSpeed = soft.boxSpeed](const Frame& frame) {
        const auto& p = j.solver()->particles();
        const double ballBottom = double(ball.getCenterOfMassPosition().y()) - 0.05;
        if (frame.index == 30) { // 0.5 s: the jelly has landed; slide the box into it
            watch->jellyXBeforeBox = centreOfMass(p).x();
            box.forceActivationState(ACTIVE_TAG);
            box.setDeactivationTime(0);
            box.setLinearVelocity(btVector3(btScalar(boxSpeed), 0, 0));
        } else if (frame.index == 120) { // 2 s: drop the ball on the jelly's middle, 0.2 m above it
            watch->jellyTop = highestPoint(p) + 0.02;
            const Eigen::Vector3d c = centreOfMass(p);
            ball.setWorldTransform(btTransform(btQuaternion::getIdentity(),
                                               btVector3(btScalar(c.x()), btScalar(watch->jellyTop + 0.25), btScalar(c.z()))));
            ball.forceActivationState(ACTIVE_TAG);
            ball.setDeactivationTime(0); // its 2 s held still would put it to sleep at once
        } else if (frame.index > 120 && watch->phase < 3) {
            // 0 falling, 1 sinking in (lowest point), 2 bouncing back up (highest), 3 done.
            const double vy = double(ball.getLinearVelocity().y());
            if (watch->phase == 0 && ballBottom < watch->jellyTop + 0.002) watch->phase = 1;
            if (watch->phase == 1 && vy > 0.0) watch->phase = 2;
            if (watch->phase == 2 && vy < 0.0) watch->phase = 3;
            if (watch->phase == 1) watch->ballLowest = std::min(watch->ballLowest, ballBottom);
            if (watch->phase == 2) watch->ballRebound = std::max(watch->ballRebound, ballBottom);
        }
        if (frame.index == 119) scene.addSummary("jelly_pushed_by_box", centreOfMass(p).x() - watch->jellyXBeforeBox);
        if (frame.index != frame.count) return;
        addDeformationSummary(scene, j);
        scene.addSummary("jelly_rest_shape_error", p.restShapeError());
        scene.addSummary("tyre_rest_shape_error", t.solver()->particles().restShapeError());
        scene.addSummary("tyre_primitives", t.shape().primitiveCount());
        scene.addSummary("ball_sink_depth", watch->jellyTop - watch->ballLowest);
        scene.addSummary("ball_rebound_height", watch->ballRebound - watch->jellyTop);
    });
}

// Adds the car and schedules the hits; returns the car body.
inline VisualBody& buildCarScene(Scene& scene, const ThrownBall& ball, int hitEveryFrames) {
    scene.addGround();
    geometry::PhysicalMeshSettings shell;
    shell.thickness = 0.01;
    shell.density = 1500;
    BodySettings car;
    car.deformation = Deformation::Plastic;
    const auto object = geometry::buildPhysicalObject(carShell().parse("car.obj"), shell);
    VisualBody& body = scene.plugin().addVisualBody(object.bodies[0], car, btTransform::getIdentity());
    printWarnings("shatter-car", body);
    auto hits = std::make_shared<int>(0);
    scene.onFrame([&scene, &body, ball, hitEveryFrames, hits](const Frame& frame) {
        if (frame.index % hitEveryFrames != 1) return;
        std::uniform_real_distribution<double> along(-1.5, 1.5), height(0.5, 1.5);
        const double side = (*hits)++ % 2 == 0 ? 1.0 : -1.0;
        const btVector3 target(btScalar(along(scene.random())), btScalar(height(scene.random())), 0);
        const btVector3 from = target + btVector3(0, 0, btScalar(2.0 * side));
        throwBall(scene, ball, from, target - from, "ball" + std::to_string(*hits));
        addDeformationSummary(scene, body);
    });
    return body;
}

} // namespace shatter::demo
