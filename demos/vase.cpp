// shatter-vase: a vase (a closed mesh of quads) and a bowl (an open surface of extruded faces)
// fall on a stone floor and shatter where they land (source 000 §2.3, §3.6): a fracture
// pattern is placed at the hardest contact, its cells cut the body's primitives, and the
// pieces fly on as rigid bodies; a piece hit hard enough again breaks once more.
#include "demos/FractureDemo.h"
#include "demos/MeshOptions.h"
#include "demos/OrientedDemo.h"
#include "demos/runner/DemoRunner.h"
#include <shatter/bullet_ext/Convert.h>
#include <shatter/plugin/geometry/PhysicalMesh.h>

#include <cmath>
#include <iostream>

namespace {

using shatter::demo::ObjText;

// A vase 32 cm tall with walls 8 mm thick: the outer surface, the lip, the inner surface and
// the floor inside and out, one closed mesh of 24 × 16 quads per wall (the floors close with
// one polygon each). Its axis is y, its foot at y = 0.
ObjText vase() {
    constexpr int around = 24, rings = 16;
    constexpr double height = 0.32, wall = 0.008, floor = 0.012;
    auto radius = [](double t) { return 0.055 + 0.035 * std::sin(M_PI * (0.15 + 1.1 * t)) + 0.02 * t * t; };
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
        const double t = double(j) / rings, y = floor + (height - floor) * t;
        ring.emplace_back();
        for (int i = 0; i < around; ++i)
            ring.back().push_back(obj.vertex(at(radius(t) - wall, 2 * M_PI * i / around, y)));
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

btTransform dropPose(double x, double height, double tiltDegrees, const Eigen::Vector3d& axis) {
    const Eigen::Isometry3d pose =
        Eigen::Translation3d(x, height, 0.0) * Eigen::AngleAxisd(tiltDegrees * M_PI / 180.0, axis.normalized());
    return shatter::toBullet(pose);
}

} // namespace

int main(int argc, char** argv) {
    shatter::demo::DemoRunner runner("vase", "A vase and a bowl dropped on a stone floor shatter where they land.");
    std::string mesh;
    runner.cli().add_option("--mesh", mesh, "OBJ file to drop and break instead of the vase and the bowl");
    shatter::geometry::PhysicalMeshSettings meshSettings;
    meshSettings.density = 2400; // fired clay
    shatter::demo::addMeshOptions(runner.cli(), meshSettings);
    shatter::BodySettings settings;
    settings.rigidBody.restitution = 0.1;
    settings.fracture.threshold = 3.0; // N·s: the vase (1.3 kg) landing at 4 m/s gives about 5
    settings.fracture.radius = 0.2;
    settings.fracture.cells = 48;
    shatter::demo::addFractureOptions(runner.cli(), settings.fracture);
    double height = 1.0;
    runner.cli().add_option("--height", height, "drop height of the lowest point, m")->capture_default_str();
    std::unique_ptr<shatter::demo::FractureSummary> summary;
    return runner.run(argc, argv, [&](shatter::demo::Scene& scene) {
        scene.addGround(0.8);
        settings.fracture.seed = scene.seed();
        summary = std::make_unique<shatter::demo::FractureSummary>(scene);
        auto drop = [&](const shatter::geometry::ObjFile& file, const shatter::geometry::PhysicalMeshSettings& how, double x,
                        double tilt, const Eigen::Vector3d& axis) {
            const auto object = shatter::geometry::buildPhysicalObject(file, how);
            for (const auto& w : object.warnings) std::cerr << "shatter-vase: warning: " << w << "\n";
            // Lift the object so its lowest point starts `height` above the floor.
            const btTransform turned = dropPose(x, 0.0, tilt, axis);
            double lowest = INFINITY;
            for (const auto& body : object.bodies)
                for (const auto& p : body.visual.positions) lowest = std::min(lowest, double((turned * shatter::toBullet(p)).y()));
            const btTransform pose = dropPose(x, height - lowest, tilt, axis);
            for (shatter::VisualBody* body : scene.plugin().addObject(object, settings, pose).bodies) summary->watch(*body);
        };
        if (!mesh.empty()) {
            drop(shatter::geometry::loadObj(mesh), meshSettings, 0.0, 20.0, {0.3, 0.0, 1.0});
        } else {
            // Each wall's faces are extruded 4 mm inward: the two walls of the vase meet.
            shatter::geometry::PhysicalMeshSettings vaseMesh = meshSettings, bowlMesh = meshSettings;
            vaseMesh.thickness = 0.004;
            bowlMesh.scale = 0.5; // the asset is 60 cm across
            bowlMesh.thickness = 0.006;
            drop(vase().parse("vase.obj"), vaseMesh, -0.25, 35.0, {0.2, 0.0, 1.0});
            drop(shatter::geometry::loadObj(std::string(SHATTER_ASSET_DIR) + "/bowl.obj"), bowlMesh, 0.35, 20.0,
                 {1.0, 0.0, 0.2});
        }
        scene.onFrame([&summary](const shatter::demo::Frame& f) { summary->frame(f); });
    });
}
