// shatter-bench-oriented: speed of the oriented-particle solver and of the shatter-car scene
// on one core. Reports medians (and the worst frame) of repeated runs, the same way each time.
//   particle-iterations/s: the car's 16,000 particles stepped as a soft body, no contacts;
//   car frames: world step of a 60 Hz frame (4 substeps), plastic-solve frames listed apart.
#include "demos/OrientedDemo.h"
#include <shatter/plugin/oriented/OrientedSolver.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <iostream>
#include <nlohmann/json.hpp>

namespace {

using Clock = std::chrono::steady_clock;

double median(std::vector<double> v) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    const size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

double seconds(Clock::time_point a, Clock::time_point b) { return std::chrono::duration<double>(b - a).count(); }

// Particle-iterations per second of soft steps over the car's particles, perturbed so every
// group has real work.
double particleIterationsPerSecond(const shatter::geometry::PhysicalMesh& mesh, int steps, std::mt19937_64& rng) {
    shatter::oriented::SolverSettings settings;
    settings.gravity.setZero();
    shatter::oriented::OrientedSolver solver(
        "car", shatter::oriented::particlesFromPrimitives(mesh.primitives, mesh.density, "car"), mesh.connections,
        settings);
    std::uniform_real_distribution<double> u(-0.5, 0.5);
    for (auto& v : solver.particles().velocity) v = {u(rng), u(rng), u(rng)};
    const auto start = Clock::now();
    for (int s = 0; s < steps; ++s) solver.step(1.0 / 240);
    return double(solver.particles().size()) * settings.iterations * steps / seconds(start, Clock::now());
}

} // namespace

int main(int argc, char** argv) {
    CLI::App app{"Oriented-particle solver and shatter-car frame times on one core."};
    int frames = 240, repeats = 3, steps = 20;
    app.add_option("--frames", frames, "car frames per run (60 Hz)")->capture_default_str()->check(CLI::PositiveNumber);
    app.add_option("--repeats", repeats, "runs; medians are over all of them")->capture_default_str()->check(CLI::PositiveNumber);
    app.add_option("--solver-steps", steps, "soft steps per particle-rate run")->capture_default_str()->check(CLI::PositiveNumber);
    CLI11_PARSE(app, argc, argv);
    try {
        std::mt19937_64 rng(1);
        const auto object = shatter::geometry::buildPhysicalObject(shatter::demo::carShell().parse("car.obj"),
                                                                   [] {
                                                                       shatter::geometry::PhysicalMeshSettings s;
                                                                       s.thickness = 0.01;
                                                                       s.density = 1500;
                                                                       return s;
                                                                   }());
        std::vector<double> rates, frameMs, plasticMs;
        for (int r = 0; r < repeats; ++r) {
            rates.push_back(particleIterationsPerSecond(object.bodies[0], steps, rng));
            shatter::demo::Scene scene(1);
            shatter::demo::ThrownBall ball{12.0, 20.0, 0.12};
            shatter::demo::buildCarScene(scene, ball, 30);
            scene.plugin().takeEvents();
            for (int f = 1; f <= frames; ++f) {
                const auto start = Clock::now();
                scene.world().stepSimulation(btScalar(1.0 / 60), 4, btScalar(1.0 / 240));
                const double ms = 1e3 * seconds(start, Clock::now());
                const auto events = scene.plugin().takeEvents();
                const bool dented = std::any_of(events.begin(), events.end(), [](const shatter::Event& e) {
                    return e.type == shatter::EventType::BodyDented;
                });
                (dented ? plasticMs : frameMs).push_back(ms);
                scene.notifyFrame({f, frames, f / 60.0, events});
            }
        }
        std::vector<double> all = frameMs;
        all.insert(all.end(), plasticMs.begin(), plasticMs.end());
        const nlohmann::ordered_json report = {
            {"primitives", object.bodies[0].primitives.size()},
            {"particle_iterations_per_second_median", median(rates)},
            {"frame_ms_median", median(all)},
            {"frame_ms_worst", *std::max_element(all.begin(), all.end())},
            {"rigid_frame_ms_median", median(frameMs)},
            {"plastic_frames", plasticMs.size()},
            {"plastic_frame_ms_median", median(plasticMs)},
            {"frames", frames},
            {"repeats", repeats}};
        std::cout << report.dump(2) << "\n";
    } catch (const std::exception& e) {
        std::cerr << "shatter-bench-oriented: error: " << e.what() << "\n";
        return 1;
    }
    return 0;
}
