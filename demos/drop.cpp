// shatter-drop: meshes of every kind (quads, intersecting boxes, an open surface, a jointed
// object) become group-shape bodies, fall on the ground and come to rest.
#include <shatter/bullet_ext/Convert.h>
#include "demos/MeshOptions.h"
#include "demos/runner/DemoRunner.h"
#include <shatter/plugin/geometry/ObjFile.h>
#include <shatter/plugin/geometry/PhysicalMesh.h>

#include <cmath>
#include <iostream>
#include <string>

namespace {

struct Drop {
    const char* file;
    double x, z, height, tiltDegrees;
};

// The built-in set, spread along x so nothing lands on anything else.
constexpr Drop kBuiltIn[] = {
    {"torus.obj", -1.6, 0.0, 0.8, 25.0},
    {"chair.obj", -0.4, 0.0, 0.1, 5.0},
    {"bowl.obj", 0.7, 0.0, 0.4, 5.0},
    {"hinged_planks.obj", 1.9, 0.0, 0.9, 30.0},
};

btTransform dropPose(const shatter::geometry::PhysicalObject& object, double x, double z, double height, double tilt) {
    // Tilt about the z axis, then lift so the lowest point starts `height` above the ground.
    const Eigen::Isometry3d r(Eigen::AngleAxisd(tilt * M_PI / 180.0, Eigen::Vector3d(0.3, 0.0, 1.0).normalized()));
    double lowest = INFINITY;
    for (const auto& body : object.bodies)
        for (const auto& p : body.visual.positions) lowest = std::min(lowest, (r * p).y());
    Eigen::Isometry3d pose = Eigen::Translation3d(x, height - lowest, z) * r;
    return shatter::toBullet(pose);
}

void printWarnings(const std::vector<std::string>& warnings) {
    for (const auto& w : warnings) std::cerr << "shatter-drop: warning: " << w << "\n";
}

} // namespace

int main(int argc, char** argv) {
    shatter::demo::DemoRunner runner("drop", "Meshes of every kind dropped on the ground, coming to rest.");
    std::string mesh;
    shatter::BodySettings settings;
    shatter::geometry::PhysicalMeshSettings meshSettings;
    runner.cli().add_option("--mesh", mesh, "OBJ file to drop instead of the built-in set");
    shatter::demo::addMeshOptions(runner.cli(), meshSettings);
    settings.rigidBody.rollingFriction = 0.001; // the bowl and the torus stop rocking as real ones do
    runner.cli().add_option("--rolling-friction", settings.rigidBody.rollingFriction, "rolling resistance lever arm in m")
        ->capture_default_str();
    return runner.run(argc, argv, [&](shatter::demo::Scene& scene) {
        scene.addGround();
        auto drop = [&](const std::string& path, double x, double z, double height, double tilt) {
            const auto file = shatter::geometry::loadObj(path);
            const auto object = shatter::geometry::buildPhysicalObject(file, meshSettings);
            printWarnings(object.warnings);
            scene.plugin().addObject(object, settings, dropPose(object, x, z, height, tilt));
        };
        if (!mesh.empty()) {
            drop(mesh, 0.0, 0.0, 0.3, 15.0);
            return;
        }
        for (const Drop& d : kBuiltIn) drop(std::string(SHATTER_ASSET_DIR) + "/" + d.file, d.x, d.z, d.height, d.tiltDegrees);
    });
}
