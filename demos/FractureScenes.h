#pragma once
// The fracture scenes, shared by their demos (shatter-vase, shatter-glass) and the fracture
// benchmark: a vase and a bowl dropped on a stone floor, and a pane of glass on two hinges hit
// by a ball. Each watches its breakable bodies with a FractureSummary.
#include "demos/FractureDemo.h"
#include "demos/OrientedDemo.h"
#include <shatter/bullet_ext/Convert.h>
#include <shatter/plugin/geometry/PhysicalMesh.h>

#include <cmath>
#include <iostream>
#include <string>
#include <vector>

namespace shatter::demo {

// A vase 32 cm tall with walls 8 mm thick: the outer surface, the lip, the inner surface and
// the floor inside and out, one closed mesh of 24 × 16 quads per wall (the floors close with
// one polygon each). Its axis is y, its foot at y = 0. The inner surface is the outer one
// moved in by the wall along the profile's normal, so the two walls' faces, each extruded
// half the wall inward, meet all round: the wall is one solid, and a cell cuts one piece of
// it, not an outer and an inner shard (a vertical offset left gaps of up to 6 mm low down).
inline ObjText vase() {
    constexpr int around = 24, rings = 16;
    constexpr double height = 0.32, wall = 0.008;
    auto radius = [](double t) { return 0.055 + 0.035 * std::sin(M_PI * (0.15 + 1.1 * t)) + 0.02 * t * t; };
    auto slope = [](double t) { // d radius / dt
        return 0.035 * 1.1 * M_PI * std::cos(M_PI * (0.15 + 1.1 * t)) + 0.04 * t;
    };
    ObjText obj;
    obj.object("vase");
    auto at = [](double r, double angle, double y) { return Eigen::Vector3d(r * std::cos(angle), y, -r * std::sin(angle)); };
    // Rings of the profile, outer from the foot up, then inner from the lip down.
    std::vector<std::vector<int>> ring;
    for (int j = 0; j <= rings; ++j) {
        const double t = double(j) / rings;
        ring.emplace_back();
        for (int i = 0; i < around; ++i) ring.back().push_back(obj.vertex(at(radius(t), 2 * M_PI * i / around, height * t)));
    }
    for (int j = rings; j >= 0; --j) {
        const double t = double(j) / rings;
        // The profile (radius(t), height t) has the outward normal (height, -slope) / length.
        const double length = std::hypot(height, slope(t));
        // The inner floor lies a wall above the foot.
        const double r = radius(t) - wall * height / length, y = j == 0 ? wall : height * t + wall * slope(t) / length;
        ring.emplace_back();
        for (int i = 0; i < around; ++i) ring.back().push_back(obj.vertex(at(r, 2 * M_PI * i / around, y)));
    }
    // Quads between consecutive rings, outward: up the outside, over the lip, down the inside.
    for (size_t j = 0; j + 1 < ring.size(); ++j)
        for (int i = 0; i < around; ++i) {
            const int k = (i + 1) % around;
            obj.face({ring[j][i], ring[j][k], ring[j + 1][k], ring[j + 1][i]});
        }
    // The two floors: the foot seen from below, the inner floor seen from above.
    std::vector<int> footIds(ring.front().rbegin(), ring.front().rend());
    obj.polygon(footIds);
    obj.polygon(ring.back());
    return obj;
}

inline btTransform dropPose(double x, double height, double tiltDegrees, const Eigen::Vector3d& axis) {
    const Eigen::Isometry3d pose =
        Eigen::Translation3d(x, height, 0.0) * Eigen::AngleAxisd(tiltDegrees * M_PI / 180.0, axis.normalized());
    return toBullet(pose);
}

// A pane 0.8 m × 0.6 m of 5 cm quads facing +z (extruded 6 mm towards −z), 2 cm above the
// frame's sill; frame posts, sill and top beam; hinge boxes over the pane's left column and
// the left post.
inline ObjText paneAndFrame() {
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


struct VaseScene {
    std::string mesh; // an OBJ to drop and break instead of the vase and the bowl
    geometry::PhysicalMeshSettings meshSettings = [] {
        geometry::PhysicalMeshSettings s;
        s.density = 2400; // fired clay
        return s;
    }();
    BodySettings settings = [] {
        BodySettings s;
        s.rigidBody.restitution = 0.1;
        s.fracture.enabled = true;
        s.fracture.threshold = 3.0; // N·s: the vase (3 kg) landing at 4.4 m/s gives about 13
        s.fracture.radius = 0.2;
        // Every shard of the vase and the bowl (all under 35 cm) whose hull is clear collides
        // as that hull: a heap of them costs hull pairs, not primitive pairs (the frames after
        // the break: median 7.1 → 3.4 ms CPU, see bullet_ext/fracture/README.md).
        s.fracture.hullBelow = 0.5;
        // The shards do not collide with each other in the 3 steps after the break: their first
        // contacts fall in the next frame, not in the break's (frame 28: 220 → 133 M
        // instructions, see bullet_ext/fracture/README.md). The price: they settle closer
        // together and touch more, so at seed 1 the median frame rises (27.7 → 39.6 M, the 240
        // frames 6.9 → 10.0 G with the spacing below); over seeds 1-4 the CPU median did not.
        s.fracture.contactDelaySteps = 3;
        // At most one break per frame of 4 steps: the bowl, landing in the vase's step, breaks
        // in the next frame (frame 28 then holds only the vase's event).
        s.fracture.eventSpacingSteps = 4;
        s.fracture.setCells(48);
        return s;
    }();
    double height = 1.0; // m, of the lowest point
};

inline void buildVaseScene(Scene& scene, VaseScene o, FractureSummary& summary) {
    scene.addGround(0.8);
    // The body breaks in the step it lands, still moving into the floor (Spot the cow, 1.7 t
    // at 4.4 m/s: 3.8 m/s after the step), so its pieces are pressed up to 2.6 cm into the
    // floor and 1.5 cm into each other; Bullet's default pushes such overlaps out with added
    // velocity, which kicked slivers to 58 rad/s 5 s later and kept the heap awake for ever.
    scene.useSplitImpulsesOnly();
    o.settings.fracture.seed = scene.seed();
    auto drop = [&](const geometry::ObjFile& file, const geometry::PhysicalMeshSettings& how, double x, double tilt,
                    const Eigen::Vector3d& axis) {
        const auto object = geometry::buildPhysicalObject(file, how);
        for (const auto& w : object.warnings) std::cerr << "shatter-vase: warning: " << w << "\n";
        // Lifted so that its lowest point starts `height` above the floor.
        const btTransform turned = dropPose(x, 0.0, tilt, axis);
        double lowest = INFINITY;
        for (const auto& body : object.bodies)
            for (const auto& p : body.visual.positions) lowest = std::min(lowest, double((turned * toBullet(p)).y()));
        const btTransform pose = dropPose(x, o.height - lowest, tilt, axis);
        for (VisualBody* body : scene.plugin().addObject(object, o.settings, pose).bodies) summary.watch(*body);
    };
    if (!o.mesh.empty()) {
        drop(geometry::loadObj(o.mesh), o.meshSettings, 0.0, 20.0, {0.3, 0.0, 1.0});
        return;
    }
    // Each wall's faces are extruded 4 mm inward: the two walls of the vase meet. Flat faces
    // on circles of 24 sides put the inner and outer faces 8 mm × cos(7.5°) apart: 0.07 mm
    // of gap, bridged by a contact tolerance of 0.2 mm (the default is 0.04 mm here).
    geometry::PhysicalMeshSettings vaseMesh = o.meshSettings, bowlMesh = o.meshSettings;
    vaseMesh.thickness = 0.004;
    vaseMesh.contactTolerance = 0.0002;
    bowlMesh.scale = 0.5; // the asset is 60 cm across
    bowlMesh.thickness = 0.006;
    drop(vase().parse("vase.obj"), vaseMesh, -0.25, 35.0, {0.2, 0.0, 1.0});
    drop(geometry::loadObj(std::string(SHATTER_ASSET_DIR) + "/bowl.obj"), bowlMesh, 0.35, 20.0, {1.0, 0.0, 0.2});
}

struct GlassScene {
    std::string mesh; // an OBJ to hang in place of the pane (its first body is watched)
    ThrownBall ball{8.0, 0.4, 0.05};
    geometry::PhysicalMeshSettings meshSettings = [] {
        geometry::PhysicalMeshSettings s;
        s.thickness = 0.006;
        s.density = 2500; // soda-lime glass
        return s;
    }();
    BodySettings pane = [] {
        BodySettings s;
        s.fracture.enabled = true;
        s.fracture.pattern = PatternKind::Glass;
        s.fracture.setCells(64);
        s.fracture.threshold = 1.0; // N·s: the ball (0.4 kg at 8 m/s) gives about 3
        s.fracture.radius = 0.25;
        s.fracture.depth = 0;
        // Every shard (under 25 cm at seed 1) collides as its hull, which is the shard itself: the
        // pane is flat and the pattern's cells are convex. After the break the shards touch
        // along every crack; as group shapes each touching pair of their primitives held a
        // manifold of up to 4 points (1,900 points a step, frames 1-20: 1,119 M instructions),
        // as hulls each touching pair of shards holds one (about 500; 493 M). The hulls do not
        // hold each other wedged in the hole as the primitives did: the shards fall out of it
        // (see bullet_ext/fracture/README.md).
        s.fracture.hullBelow = 0.5;
        return s;
    }();
};

inline void buildGlassScene(Scene& scene, GlassScene o, FractureSummary& summary) {
    scene.addGround();
    scene.useSplitImpulsesOnly(); // the shards land as the vase's do (buildVaseScene)
    o.pane.fracture.seed = scene.seed();
    const auto file = o.mesh.empty() ? paneAndFrame().parse("glass.obj") : geometry::loadObj(o.mesh);
    const auto object = geometry::buildPhysicalObject(file, o.meshSettings);
    for (const auto& w : object.warnings) std::cerr << "shatter-glass: warning: " << w << "\n";
    BodySettings frame;
    frame.dynamic = false;
    const auto added = scene.plugin().addObject(object, o.pane, btTransform::getIdentity(), {{"frame", frame}});
    summary.watch(*added.bodies[0]);
    throwBall(scene, o.ball, btVector3(0.58f, 0.9f, 0.6f), btVector3(0, 0, -1), "ball");
}

} // namespace shatter::demo
