#pragma once
// What the oriented-particle demos (door, soft, car) and their benchmark share: meshes
// generated as OBJ text (so they go through the same loader and physical-mesh rules as a
// user's file), the ball they throw, and the summary keys.
#include "demos/runner/Scene.h"
#include <shatter/plugin/geometry/ObjFile.h>
#include <shatter/plugin/geometry/PhysicalMesh.h>

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
