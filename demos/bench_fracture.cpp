// shatter-bench-fracture: how long a fracture event takes, and the frame times of scenes where
// bodies break, on one core. JSON on the last line of the output.
//   events: a Voronoi pattern of 16, 64 or 256 cells placed at the side of a car-like shell of
//   about 100, 1,000 or 16,000 extruded quads (each primitive a body part); time per phase
//   (placement, cutting, islands, visual meshes, body creation), median over repeats;
//   frames: the shatter-vase and shatter-glass scenes at 60 Hz with 4 substeps, Bullet
//   included: median, 99th percentile and worst frame, in wall time and in this thread's CPU
//   time (which a shared machine's waiting leaves out).
//   subdivisions (--subdivision all|SHELL runs only these): the same shells and patterns with a plastic
//   body in FractureMode::Subdivide: the cut, its re-assembly as one body, and the body's
//   rebuild (shape, particles, mass) per event, median and worst over repeats.
// --primitives P --cells C: one event case only, no scenes nor subdivisions (for callgrind).
// --scene vase|glass: the frames of that scene only (for profiling its contacts).
#include "demos/FractureScenes.h"
#include "demos/bench/ContactOptions.h"
#include "demos/bench/FrameStats.h"


#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <ctime>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>

namespace {

using Clock = std::chrono::steady_clock;
using shatter::bench::percentile;

// CPU time of this thread (ms): on a machine shared with other jobs, it leaves out the time
// the thread waited for a core, which wall times include.
double threadCpuMs() {
    timespec t{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return 1e3 * double(t.tv_sec) + 1e-6 * double(t.tv_nsec);
}

struct Shell {
    const char* name;
    int nu, nv;
};
// Primitive counts 96 (12 × 8), 1,000 (40 × 25) and 16,000 (200 × 80).
constexpr Shell kShells[] = {{"shell_100", 12, 8}, {"shell_1000", 40, 25}, {"shell_16000", 200, 80}};

nlohmann::ordered_json timeEvents(const Shell& shell, int cells, int repeats) {
    shatter::geometry::PhysicalMeshSettings how;
    how.thickness = 0.01;
    how.density = 1500;
    const auto object = shatter::geometry::buildPhysicalObject(shatter::demo::carShell(shell.nu, shell.nv).parse("car.obj"), how);
    std::vector<double> placement, cutting, islands, visual, bodies, total, cpu, shown;
    int fragments = 0, cut = 0;
    for (int r = 0; r < repeats; ++r) {
        shatter::demo::Scene scene(1);
        shatter::BodySettings s;
        s.fracture.enabled = true;
        s.fracture.setCells(cells);
        s.fracture.radius = 0.8;
        s.fracture.seed = std::uint64_t(r + 1);
        shatter::VisualBody& body = scene.plugin().addVisualBody(object.bodies[0], s, btTransform::getIdentity());
        auto& system = scene.plugin().fractures();
        system.resetTiming();
        // The driver's door, hit from the side (+z is outward there).
        const double cpuStart = threadCpuMs();
        const auto pieces = scene.plugin().fracture(body, btVector3(0.3f, 1.0f, 0.9f), btVector3(0, 0, -1));
        cpu.push_back(threadCpuMs() - cpuStart);
        // Plus each new fragment's first visualMesh() (its welder and world faces, made then,
        // and its weld): what the event left for a renderer that asks for world-space meshes.
        // The rest's weld is not counted (it was never part of the event).
        const double showStart = threadCpuMs();
        for (shatter::VisualBody* piece : pieces)
            if (piece != &body) piece->visualMesh();
        shown.push_back(cpu.back() + threadCpuMs() - showStart);
        const auto& t = system.timing();
        placement.push_back(1e3 * t.placement);
        cutting.push_back(1e3 * t.cutting);
        islands.push_back(1e3 * t.islands);
        visual.push_back(1e3 * t.visualMesh);
        bodies.push_back(1e3 * t.bodies);
        total.push_back(1e3 * (t.placement + t.cutting + t.islands + t.visualMesh + t.bodies));
        fragments = int(pieces.size());
        cut = t.primitivesCut;
    }
    return {{"body", shell.name},
            {"primitives", object.bodies[0].primitives.size()},
            {"cells", cells},
            {"fragments", fragments},
            {"primitives_cut", cut},
            {"placement_ms", percentile(placement, 0.5)},
            {"cutting_ms", percentile(cutting, 0.5)},
            {"islands_ms", percentile(islands, 0.5)},
            {"visual_mesh_ms", percentile(visual, 0.5)},
            {"bodies_ms", percentile(bodies, 0.5)},
            {"total_ms_median", percentile(total, 0.5)},
            {"total_ms_worst", percentile(total, 1.0)},
            {"cpu_ms_median", percentile(cpu, 0.5)},
            {"cpu_ms_worst", percentile(cpu, 1.0)},
            {"cpu_ms_with_first_show_median", percentile(shown, 0.5)}};
}

// Sum of every body's position and velocity components: equal sums say two runs (with a
// setting that must not change the physics) ended in the same state.
double stateChecksum(const shatter::Plugin& plugin) {
    double sum = 0;
    for (const auto& b : plugin.bodies()) {
        const btRigidBody& r = b->rigidBody();
        for (int k = 0; k < 3; ++k)
            sum += double(r.getCenterOfMassPosition()[k]) + double(r.getLinearVelocity()[k]) +
                   double(r.getAngularVelocity()[k]);
    }
    return sum;
}

template <class Build>
nlohmann::ordered_json timeFrames(const char* name, int frames, unsigned seed, const Build& build) {
    shatter::demo::Scene scene(seed);
    shatter::demo::FractureSummary summary(scene);
    build(scene, summary);
    scene.plugin().takeEvents();
    std::vector<double> ms, cpu;
    for (int f = 1; f <= frames; ++f) {
        const auto start = Clock::now();
        const double cpuStart = threadCpuMs();
        scene.world().stepSimulation(btScalar(1.0 / 60), 4, btScalar(1.0 / 240));
        cpu.push_back(threadCpuMs() - cpuStart);
        ms.push_back(1e3 * std::chrono::duration<double>(Clock::now() - start).count());
        summary.frame({f, frames, f / 60.0, scene.plugin().takeEvents()});
    }
    return {{"scene", name},
            {"seed", seed},
            {"frames", frames},
            {"fracture_events", summary.events()},
            {"frame_ms_median", percentile(ms, 0.5)},
            {"frame_ms_p99", percentile(ms, 0.99)},
            {"frame_ms_worst", percentile(ms, 1.0)},
            {"frame_cpu_ms_median", percentile(cpu, 0.5)},
            {"frame_cpu_ms_p99", percentile(cpu, 0.99)},
            {"frame_cpu_ms_worst", percentile(cpu, 1.0)},
            {"frame_cpu_worst_at", int(std::max_element(cpu.begin(), cpu.end()) - cpu.begin()) + 1},
            {"bodies", scene.plugin().bodies().size()},
            {"state_checksum", stateChecksum(scene.plugin())},
            {"frame_cpu_ms", cpu}};
}

// A subdivision event (issue 17): the body stays, cut finer where hit.
nlohmann::ordered_json timeSubdivision(const Shell& shell, int cells, int repeats) {
    shatter::geometry::PhysicalMeshSettings how;
    how.thickness = 0.01;
    how.density = 1500;
    const auto object = shatter::geometry::buildPhysicalObject(shatter::demo::carShell(shell.nu, shell.nv).parse("car.obj"), how);
    std::vector<double> cutting, assembly, body, total;
    int after = 0, cut = 0;
    for (int r = 0; r < repeats; ++r) {
        shatter::demo::Scene scene(1);
        shatter::BodySettings s;
        s.deformation = shatter::Deformation::Plastic;
        s.fracture.enabled = true;
        s.fracture.mode = shatter::FractureMode::Subdivide;
        s.fracture.setCells(cells);
        s.fracture.radius = 0.8;
        s.fracture.seed = std::uint64_t(r + 1);
        shatter::VisualBody& car = scene.plugin().addVisualBody(object.bodies[0], s, btTransform::getIdentity());
        auto& system = scene.plugin().fractures();
        system.resetTiming();
        scene.plugin().fracture(car, btVector3(0.3f, 1.0f, 0.9f), btVector3(0, 0, -1));
        const auto& t = system.timing();
        cutting.push_back(1e3 * t.cutting);
        assembly.push_back(1e3 * t.visualMesh);
        body.push_back(1e3 * t.bodies);
        total.push_back(1e3 * (t.placement + t.cutting + t.visualMesh + t.bodies));
        after = car.shape().primitiveCount();
        cut = t.primitivesCut;
    }
    return {{"body", shell.name},
            {"primitives", object.bodies[0].primitives.size()},
            {"cells", cells},
            {"primitives_after", after},
            {"primitives_cut", cut},
            {"cutting_ms", percentile(cutting, 0.5)},
            {"assembly_ms", percentile(assembly, 0.5)},
            {"body_rebuild_ms", percentile(body, 0.5)},
            {"total_ms_median", percentile(total, 0.5)},
            {"total_ms_worst", percentile(total, 1.0)}};
}

} // namespace

int main(int argc, char** argv) {
    CLI::App app{"Fracture events by body size and pattern cells, and frame times of breaking scenes, on one core."};
    int repeats = 5, frames = 180;
    int onlyPrimitives = 0, onlyCells = 0; // one event case only, no scenes (for callgrind)
    app.add_option("--repeats", repeats, "fracture events per body and cell count (medians)")
        ->capture_default_str()
        ->check(CLI::PositiveNumber);
    app.add_option("--frames", frames, "frames of each breaking scene")->capture_default_str()->check(CLI::PositiveNumber);
    std::string subdivisionOnly; // empty: every section
    app.add_option("--subdivision", subdivisionOnly,
                   "time only subdivision events (FractureMode::Subdivide): of every shell (all) or of one "
                   "(shell_100, shell_1000, shell_16000)");
    app.add_option("--primitives", onlyPrimitives, "only this body (100, 1000 or 16000), no scenes")
        ->check(CLI::IsMember({100, 1000, 16000}));
    app.add_option("--cells", onlyCells, "only this cell count (16, 64 or 256), no scenes")
        ->check(CLI::IsMember({16, 64, 256}));
    unsigned seed = 1;
    app.add_option("--seed", seed, "seed of the breaking scenes")->capture_default_str();
    std::string sceneOnly; // empty: every section
    app.add_option("--scene", sceneOnly, "only the frames of this scene, no events nor subdivisions")
        ->check(CLI::IsMember({"vase", "glass"}));
    int contactDelay = -1; // each scene's own
    app.add_option("--contact-delay", contactDelay,
                   "steps in which the bodies of a break do not collide with each other "
                   "(FractureSettings::contactDelaySteps; default: each scene's own)")
        ->check(CLI::NonNegativeNumber);
    int eventSpacing = -1; // each scene's own
    app.add_option("--event-spacing", eventSpacing,
                   "world steps between fracture events (FractureSettings::eventSpacingSteps; default: each scene's own)")
        ->check(CLI::NonNegativeNumber);
    shatter::bench::addContactOptions(app);
    CLI11_PARSE(app, argc, argv);
    const bool one = onlyPrimitives > 0 || onlyCells > 0;
    shatter::demo::VaseScene vase;
    shatter::demo::GlassScene glass;
    if (contactDelay >= 0) {
        vase.settings.fracture.contactDelaySteps = contactDelay;
        glass.pane.fracture.contactDelaySteps = contactDelay;
    }
    if (eventSpacing >= 0) {
        vase.settings.fracture.eventSpacingSteps = eventSpacing;
        glass.pane.fracture.eventSpacingSteps = eventSpacing;
    }
    const auto buildVase = [&](auto& scene, auto& summary) { shatter::demo::buildVaseScene(scene, vase, summary); };
    const auto buildGlass = [&](auto& scene, auto& summary) { shatter::demo::buildGlassScene(scene, glass, summary); };
    try {
        if (!sceneOnly.empty()) {
            const auto build = [&](auto& scene, auto& summary) {
                if (sceneOnly == "vase") buildVase(scene, summary);
                else buildGlass(scene, summary);
            };
            std::cout << nlohmann::ordered_json{{"scenes", {timeFrames(sceneOnly.c_str(), frames, seed, build)}}}.dump() << "\n";
            return 0;
        }
        nlohmann::ordered_json subdivisions = nlohmann::ordered_json::array();
        for (const Shell& shell : kShells)
            for (int cells : {16, 64, 256}) {
                if (one || (!subdivisionOnly.empty() && subdivisionOnly != "all" && subdivisionOnly != shell.name))
                    continue;
                subdivisions.push_back(timeSubdivision(shell, cells, repeats));
                std::cout << subdivisions.back().dump() << "\n" << std::flush;
            }
        if (!subdivisionOnly.empty()) {
            std::cout << nlohmann::ordered_json{{"subdivisions", subdivisions}, {"repeats", repeats}}.dump() << "\n";
            return 0;
        }
        nlohmann::ordered_json events = nlohmann::ordered_json::array();
        for (const Shell& shell : kShells)
            for (int cells : {16, 64, 256}) {
                if (onlyPrimitives > 0 && std::string(shell.name) != "shell_" + std::to_string(onlyPrimitives)) continue;
                if (onlyCells > 0 && cells != onlyCells) continue;
                events.push_back(timeEvents(shell, cells, repeats));
                std::cout << events.back().dump() << "\n" << std::flush;
            }
        nlohmann::ordered_json scenes = nlohmann::ordered_json::array();
        if (one) {
            std::cout << nlohmann::ordered_json{{"events", events}, {"repeats", repeats}}.dump() << "\n";
            return 0;
        }
        scenes.push_back(timeFrames("vase", frames, seed, buildVase));
        std::cout << scenes.back().dump() << "\n";
        scenes.push_back(timeFrames("glass", frames, seed, buildGlass));
        std::cout << scenes.back().dump() << "\n";
        std::cout << nlohmann::ordered_json{{"events", events}, {"scenes", scenes}, {"subdivisions", subdivisions},
                                            {"repeats", repeats}}
                         .dump()
                  << "\n";
    } catch (const std::exception& e) {
        std::cerr << "shatter-bench-fracture: error: " << e.what() << "\n";
        return 1;
    }
    return 0;
}
