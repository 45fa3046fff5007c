// shatter-soft: a jelly block and a soft tyre dropped on the ground, then a ball dropped on
// the jelly and a heavy box slid into it. Both soft bodies are oriented-particle bodies every
// step (source 000 §3.2), coupled two ways to the Bullet bodies they touch: the ball sinks
// into the jelly and the box shoves it along the ground.
#include "demos/OrientedDemo.h"
#include "demos/runner/DemoRunner.h"
#include <shatter/plugin/geometry/PhysicalMesh.h>


int main(int argc, char** argv) {
    shatter::demo::DemoRunner runner(
        "soft", "A jelly block and a soft tyre dropped; a ball sinks into the jelly and a heavy box shoves it.");
    shatter::demo::SoftScene soft;
    runner.cli().add_option("--jelly-stiffness", soft.jelly.solver.stiffness, "shape-matching stiffness, [0, 1]")
        ->capture_default_str();
    runner.cli().add_option("--tyre-stiffness", soft.tyre.solver.stiffness, "shape-matching stiffness, [0, 1]")
        ->capture_default_str();
    runner.cli().add_option("--jelly-iterations", soft.jelly.solver.iterations, "projection sweeps per step")
        ->capture_default_str()->check(CLI::PositiveNumber);
    runner.cli().add_option("--tyre-iterations", soft.tyre.solver.iterations, "projection sweeps per step")
        ->capture_default_str()->check(CLI::PositiveNumber);
    runner.cli().add_option("--ball-mass", soft.ballMass, "kg of the ball dropped on the jelly at 2 s")
        ->capture_default_str()->check(CLI::PositiveNumber);
    runner.cli().add_option("--box-mass", soft.boxMass, "kg of the box slid into the jelly at 0.5 s")
        ->capture_default_str()->check(CLI::PositiveNumber);
    runner.cli().add_option("--box-speed", soft.boxSpeed, "m/s of the box when it is launched")
        ->capture_default_str()->check(CLI::NonNegativeNumber);
    return runner.run(argc, argv, [&](shatter::demo::Scene& scene) { shatter::demo::buildSoftScene(scene, soft); });
}
