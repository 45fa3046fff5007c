// shatter-car: a car-like shell of 16,000 primitives resting on the ground, hit by a ball
// every half second from a seeded random side. It stays one cheap rigid body between hits and
// dents where each hit is hard enough (source 000 §3.5). The scene of shatter-bench-oriented.
#include "demos/OrientedDemo.h"
#include "demos/runner/DemoRunner.h"
#include <shatter/plugin/geometry/PhysicalMesh.h>



int main(int argc, char** argv) {
    shatter::demo::DemoRunner runner("car", "A 16,000-primitive car shell hit by balls: rigid between hits, dented by them.");
    shatter::demo::ThrownBall ball;
    ball.mass = 20.0;
    ball.speed = 12.0;
    shatter::demo::addBallOptions(runner.cli(), ball);
    int every = 30;
    runner.cli().add_option("--hit-every", every, "frames between balls")->capture_default_str()->check(CLI::PositiveNumber);
    return runner.run(argc, argv, [&](shatter::demo::Scene& scene) {
        shatter::VisualBody& car = shatter::demo::buildCarScene(scene, ball, every);
        scene.onFrame([&scene, &car](const shatter::demo::Frame&) { shatter::demo::addDeformationSummary(scene, car); });
    });
}
