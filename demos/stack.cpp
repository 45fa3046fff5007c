// shatter-stack: open crates, each a group shape of extruded quads, stacked on the ground.
// The stack must stay standing: resting contact between group shapes without jitter or drift.
#include <shatter/bullet_ext/Convert.h>
#include "demos/runner/DemoRunner.h"
#include <shatter/plugin/geometry/PhysicalMesh.h>

#include <array>
#include <cmath>
#include <iostream>

namespace {

// An open-top box of side `size` whose five sides are `cells` x `cells` quads, outward facing.
shatter::geometry::PhysicalMesh openCrate(double size, int cells, double thickness) {
    std::vector<Eigen::Vector3d> positions;
    std::vector<std::vector<int>> faces;
    // Each side: an origin corner and two edge directions whose cross product points outward.
    const double h = size / 2;
    const std::array<std::array<Eigen::Vector3d, 3>, 5> sides = {{
        {Eigen::Vector3d(-h, 0, -h), Eigen::Vector3d(size, 0, 0), Eigen::Vector3d(0, 0, size)},   // bottom (-y)
        {Eigen::Vector3d(-h, 0, h), Eigen::Vector3d(size, 0, 0), Eigen::Vector3d(0, size, 0)},    // front (+z)
        {Eigen::Vector3d(h, 0, -h), Eigen::Vector3d(-size, 0, 0), Eigen::Vector3d(0, size, 0)},   // back (-z)
        {Eigen::Vector3d(h, 0, h), Eigen::Vector3d(0, 0, -size), Eigen::Vector3d(0, size, 0)},    // right (+x)
        {Eigen::Vector3d(-h, 0, -h), Eigen::Vector3d(0, 0, size), Eigen::Vector3d(0, size, 0)},   // left (-x)
    }};
    for (const auto& [origin, u, v] : sides) {
        const int base = int(positions.size());
        for (int j = 0; j <= cells; ++j)
            for (int i = 0; i <= cells; ++i) positions.push_back(origin + u * (double(i) / cells) + v * (double(j) / cells));
        for (int j = 0; j < cells; ++j)
            for (int i = 0; i < cells; ++i) {
                const int a = base + j * (cells + 1) + i;
                faces.push_back({a, a + cells + 1, a + cells + 2, a + 1});
            }
    }
    shatter::geometry::PhysicalMeshSettings settings;
    settings.thickness = thickness;
    settings.density = 600.0; // wood
    return shatter::geometry::buildPhysicalMesh("crate", positions, faces, settings);
}

} // namespace

int main(int argc, char** argv) {
    shatter::demo::DemoRunner runner("stack", "A stack of open crates (group shapes) that stays standing.");
    int height = 6;
    int cells = 3;
    double size = 0.5;
    runner.cli().add_option("--height", height, "number of crates in the stack")->check(CLI::Range(1, 100));
    runner.cli().add_option("--cells", cells, "quads per crate side edge")->check(CLI::Range(1, 40));
    runner.cli().add_option("--size", size, "crate side in m")->check(CLI::Range(0.05, 10.0));
    shatter::VisualBody* top = nullptr;
    btVector3 topStart;
    return runner.run(argc, argv, [&](shatter::demo::Scene& scene) {
        scene.addGround();
        shatter::geometry::PhysicalMesh crate = openCrate(size, cells, 0.04 * size);
        shatter::BodySettings settings;
        for (int i = 0; i < height; ++i) {
            crate.name = "crate" + std::to_string(i);
            // A small gap so each crate settles onto the one below.
            const btTransform pose(btQuaternion::getIdentity(), btVector3(0, btScalar(i * (size + 0.002) + 0.001), 0));
            top = &scene.plugin().addVisualBody(crate, settings, pose);
        }
        topStart = top->rigidBody().getCenterOfMassPosition();
        scene.onFrame([&](const shatter::demo::Frame& frame) {
            if (frame.index != frame.count) return;
            const btVector3 d = top->rigidBody().getCenterOfMassPosition() - topStart;
            scene.addSummary("top_horizontal_drift", std::hypot(double(d.x()), double(d.z())));
            scene.addSummary("top_vertical_change", double(d.y()));
            scene.addSummary("standing", std::abs(double(d.y())) < 0.25 * size);
        });
    });
}
