// shatter-soft: a jelly block and a soft tyre dropped on the ground. Both are oriented-particle
// bodies every step (source 000 §3.2): they squash, wobble and come to rest in their rest
// shapes.
#include "demos/OrientedDemo.h"
#include "demos/runner/DemoRunner.h"
#include <shatter/plugin/geometry/PhysicalMesh.h>

#include <iostream>

namespace {

using shatter::demo::ObjText;

// n³ closed cubes of side h, each inset by 0.1 µm so that neighbours share no vertex (shared
// vertices would weld them into one part); they still touch within the contact tolerance.
ObjText jelly(int n, double h, const Eigen::Vector3d& corner) {
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

} // namespace

int main(int argc, char** argv) {
    shatter::demo::DemoRunner runner("soft", "A jelly block and a soft tyre dropped: they wobble and recover.");
    shatter::BodySettings jellySettings, tyreSettings;
    jellySettings.deformation = tyreSettings.deformation = shatter::Deformation::Soft;
    jellySettings.solver.stiffness = 0.005; // per sweep: 4 sweeps at 240 Hz still hold it; lower wobbles more
    jellySettings.solver.damping = 1.0;
    tyreSettings.solver.stiffness = 0.2;
    runner.cli().add_option("--jelly-stiffness", jellySettings.solver.stiffness, "shape-matching stiffness, [0, 1]")
        ->capture_default_str();
    runner.cli().add_option("--tyre-stiffness", tyreSettings.solver.stiffness, "shape-matching stiffness, [0, 1]")
        ->capture_default_str();
    shatter::geometry::PhysicalMeshSettings tyreMeshSettings;
    tyreMeshSettings.thickness = 0.02;
    return runner.run(argc, argv, [&](shatter::demo::Scene& scene) {
        scene.addGround();
        const auto jellyMesh = shatter::geometry::buildPhysicalObject(
            jelly(5, 0.04, {-0.6, 0.3, -0.1}).parse("jelly.obj"), {});
        ObjText tyre;
        tyre.object("tyre");
        shatter::demo::torus(tyre, 0.3, 0.1, 36, 12, {0.5, 0.5, 0.0});
        const auto tyreMesh = shatter::geometry::buildPhysicalObject(tyre.parse("tyre.obj"), tyreMeshSettings);
        auto& plugin = scene.plugin();
        shatter::VisualBody& j = plugin.addVisualBody(jellyMesh.bodies[0], jellySettings, btTransform::getIdentity());
        const btTransform tilt(btQuaternion(btVector3(0, 0, 1), 0.3f));
        shatter::VisualBody& t = plugin.addVisualBody(tyreMesh.bodies[0], tyreSettings, tilt);
        shatter::demo::printWarnings("shatter-soft", j);
        shatter::demo::printWarnings("shatter-soft", t);
        scene.onFrame([&scene, &j, &t](const shatter::demo::Frame&) {
            shatter::demo::addDeformationSummary(scene, j);
            scene.addSummary("jelly_rest_shape_error", j.solver()->particles().restShapeError());
            scene.addSummary("tyre_rest_shape_error", t.solver()->particles().restShapeError());
            scene.addSummary("tyre_primitives", t.shape().primitiveCount());
        });
    });
}
