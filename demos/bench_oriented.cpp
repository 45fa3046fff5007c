// shatter-bench-oriented: speed of the oriented-particle solver, of shatter-soft's scene, of a
// 5,000-primitive soft sheet, of shatter-tear's 2,500-quad curtain (not tearing) and of the
// shatter-car scene, on one core. Every frame is a 60 Hz world step of 4 substeps plus, for
// soft bodies, their visual mesh (a renderer asks for it every frame). Reported per scene:
// median, 99th percentile and worst frame, in wall-clock and in this thread's CPU time (which
// other processes on a busy machine disturb less), and the CPU time of the last second of
// frames (what a body that has come to rest costs); the soft scene also without self-contact,
// which prices it.
//   particle-iterations/s: particles × solver iterations × solver steps per frame over the
//   median frame (Bullet included); for the car, its 16,000 particles stepped alone.
#include "demos/OrientedDemo.h"
#include "demos/runner/PngRenderer.h"
#include <shatter/bullet_ext/shape/HullPairContacts.h>
#include <shatter/plugin/oriented/OrientedSolver.h>

#include <BulletCollision/CollisionShapes/btBoxShape.h>
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <filesystem>
#include <functional>
#include <iostream>
#include <nlohmann/json.hpp>

namespace {

using Clock = std::chrono::steady_clock;
using shatter::demo::Scene;

double quantile(std::vector<double> v, double q) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    const double at = q * double(v.size() - 1);
    const size_t lo = size_t(at);
    const size_t hi = std::min(lo + 1, v.size() - 1);
    return v[lo] + (at - double(lo)) * (v[hi] - v[lo]);
}

double seconds(Clock::time_point a, Clock::time_point b) { return std::chrono::duration<double>(b - a).count(); }

double threadCpuSeconds() {
    timespec t{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

nlohmann::ordered_json stats(const std::vector<double>& ms) {
    return {{"median", quantile(ms, 0.5)}, {"p99", quantile(ms, 0.99)}, {"worst", quantile(ms, 1.0)}};
}

// Frame times of a scene: wall-clock and thread CPU milliseconds per frame, plus the frames
// that `special` flags (the car's dents) apart.
struct Timed {
    std::vector<double> wall, cpu, specialWall;
    std::vector<double> lastSecondCpu; // the last 60 frames of each run: a body come to rest
};

// Steps a scene `frames` frames (60 Hz, 4 substeps of 1/240 s); each frame also fetches every
// soft body's visual mesh.
void runFrames(Scene& scene, int frames, Timed& out, const std::function<bool(const std::vector<shatter::Event>&)>& special) {
    std::vector<shatter::VisualBody*> soft;
    for (const auto& mesh : scene.plugin().bodies())
        if (mesh->deformation() == shatter::Deformation::Soft) soft.push_back(mesh.get());
    scene.plugin().takeEvents();
    for (int f = 1; f <= frames; ++f) {
        const auto start = Clock::now();
        const double cpu = threadCpuSeconds();
        scene.world().stepSimulation(btScalar(1.0 / 60), 4, btScalar(1.0 / 240));
        for (shatter::VisualBody* body : soft) body->visualMesh();
        const double ms = 1e3 * seconds(start, Clock::now());
        const double cpuMs = 1e3 * (threadCpuSeconds() - cpu);
        const auto events = scene.plugin().takeEvents();
        if (special && special(events)) out.specialWall.push_back(ms);
        else out.wall.push_back(ms), out.cpu.push_back(cpuMs);
        if (f > frames - 60) out.lastSecondCpu.push_back(cpuMs);
        scene.notifyFrame({f, frames, f / 60.0, events});
    }
}

// Particles × iterations × substeps of every soft body in the scene, per frame.
double particleIterationsPerFrame(Scene& scene) {
    double n = 0.0;
    for (const auto& body : scene.plugin().bodies())
        if (body->deformation() == shatter::Deformation::Soft)
            n += double(body->solver()->particles().size()) * body->settings().solver.iterations * 4;
    return n;
}

// A 2 m square soft sheet of cells × cells extruded quads (1 cm thick) dropped from 0.5 m onto
// a static table 1 m wide, so that it drapes over the edges and lies on the ground.
void buildSheetScene(Scene& scene, int cells, int iterations, int rotationIterations, int substepsPerStep,
                     double sleepSpeed, shatter::oriented::SimdPath simdPath, double stiffness, double chebyshevRadius) {
    scene.addGround();
    scene.addRigidBody(std::make_unique<btBoxShape>(btVector3(0.5f, 0.3f, 0.5f)), 0.0,
                       btTransform(btQuaternion::getIdentity(), btVector3(0, 0.3f, 0)), "table");
    shatter::demo::ObjText sheet;
    sheet.object("sheet");
    const double size = 2.0;
    sheet.surface(cells, cells, false, false, [&](int i, int j) {
        return Eigen::Vector3d(-0.5 * size + size * i / cells, 1.1, 0.5 * size - size * j / cells);
    });
    shatter::geometry::PhysicalMeshSettings mesh;
    mesh.thickness = 0.01;
    mesh.density = 500;
    shatter::BodySettings settings;
    settings.deformation = shatter::Deformation::Soft;
    // By default 3 sweeps of stiffness 0.33, Chebyshev-accelerated with ρ = 0.65: calibrated
    // to drape as the sheet of 4 plain sweeps of 0.3 (lowest particle, mean height and extents
    // at frame 240 within 5 mm, 0.2 mm and 8 mm; README, soft sheet) for 3/4 of the sweeps.
    // `stiffness` 0 takes the stiffness of a whole step of 4 sweeps of 0.3,
    // s = 1 − (1 − k)^sweeps, over `iterations` sweeps (at 3 plain sweeps that sheet is softer:
    // its lowest particle 3.5 cm lower). The solver steps every substep whatever substepsPerStep
    // is (SolverSettings).
    settings.solver.iterations = iterations;
    settings.solver.rotationIterations = rotationIterations;
    settings.solver.substepsPerStep = substepsPerStep;
    settings.solver.simdPath = simdPath;
    settings.solver.chebyshevRadius = chebyshevRadius;
    settings.solver.stiffness = stiffness > 0.0 ? stiffness : 1.0 - std::pow(0.7, 4.0 / iterations);
    settings.solver.damping = 1.0;
    // At 1 cm/s it sleeps after 8.3 s (every particle under that for half a second; its drape
    // swings down with the damping, e^(−t)), so only longer runs (--frames 600) see it.
    settings.solver.sleepSpeed = sleepSpeed;
    const auto object = shatter::geometry::buildPhysicalObject(sheet.parse("sheet.obj"), mesh);
    scene.plugin().addVisualBody(object.bodies[0], settings, btTransform::getIdentity());
}

// shatter-tear's curtain without tearing (the cost of its soft step alone): cells × cells quads
// (2 m square, 1 cm thick, 150 kg/m³, stiffness 0.5, damping 1/s) hanging from a static rail by
// eight ball-joint boxes along its top row, hit in the middle by a 5 kg ball at 12 m/s.
void buildCurtainScene(Scene& scene, int cells) {
    scene.addGround();
    shatter::demo::ObjText obj;
    obj.object("curtain");
    const double size = 2.0, bottom = 0.3;
    obj.surface(cells, cells, false, false, [&](int i, int j) {
        return Eigen::Vector3d(-0.5 * size + size * i / cells, bottom + size * j / cells, 0.0);
    });
    obj.object("rail");
    obj.box({-1.1, bottom + size + 0.02, -0.03}, {1.1, bottom + size + 0.08, 0.03});
    for (int k = 0; k < 8; ++k) {
        const double x = -0.875 + 0.25 * k;
        obj.object("joint.ball.rail.curtain." + std::to_string(k + 1));
        obj.box({x - 0.03, bottom + size - 0.02, -0.02}, {x + 0.03, bottom + size + 0.04, 0.02});
    }
    shatter::geometry::PhysicalMeshSettings mesh;
    mesh.thickness = 0.01;
    mesh.density = 150;
    shatter::BodySettings cloth;
    cloth.deformation = shatter::Deformation::Soft;
    cloth.solver.stiffness = 0.5;
    cloth.solver.damping = 1.0;
    shatter::BodySettings rail;
    rail.dynamic = false;
    const auto object = shatter::geometry::buildPhysicalObject(obj.parse("curtain.obj"), mesh);
    scene.plugin().addObject(object, cloth, btTransform::getIdentity(), {{"rail", rail}});
    shatter::demo::throwBall(scene, {12.0, 5.0, 0.12}, btVector3(0, btScalar(bottom + 0.5 * size), 1.0f),
                             btVector3(0, 0, -1), "ball");
}

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

// Where the soft bodies' particles are at the end of a run: their box and mean height (Y),
// to compare runs of a scene under other settings.
nlohmann::ordered_json softPose(Scene& scene) {
    Eigen::AlignedBox3d box;
    double height = 0.0;
    int count = 0;
    for (const auto& body : scene.plugin().bodies())
        if (body->deformation() == shatter::Deformation::Soft)
            for (const Eigen::Vector3d& x : body->solver()->particles().position) {
                box.extend(x);
                height += x.y();
                ++count;
            }
    return {{"min", {box.min().x(), box.min().y(), box.min().z()}},
            {"max", {box.max().x(), box.max().y(), box.max().z()}},
            {"mean_height", count ? height / count : 0.0}};
}

// `picture` (a .png path; none when empty): the first run's last frame.
nlohmann::ordered_json softReport(const std::string& name, const std::function<void(Scene&)>& build, int frames,
                                  int repeats, const std::string& picture) {
    Timed timed;
    int primitives = 0;
    double perFrame = 0.0;
    nlohmann::ordered_json pose;
    for (int r = 0; r < repeats; ++r) {
        Scene scene(1);
        build(scene);
        primitives = 0;
        for (const auto& body : scene.plugin().bodies())
            if (body->deformation() == shatter::Deformation::Soft) primitives += body->shape().primitiveCount();
        perFrame = particleIterationsPerFrame(scene);
        runFrames(scene, frames, timed, nullptr);
        if (r > 0) continue;
        pose = softPose(scene);
        if (picture.empty()) continue;
        const auto meshes = scene.meshes();
        const shatter::demo::Picture frame{1280, 720, "shatter-bench-oriented: " + name,
                                           "frame " + std::to_string(frames)};
        shatter::demo::renderPng(meshes, shatter::demo::frameScene(meshes, frame), frame, picture);
    }
    return {{"scene", name},
            {"soft_primitives", primitives},
            {"final_particles", pose},
            {"frame_ms", stats(timed.wall)},
            {"frame_cpu_ms", stats(timed.cpu)},
            {"last_second_frame_cpu_ms", stats(timed.lastSecondCpu)},
            {"particle_iterations_per_second", perFrame / (1e-3 * quantile(timed.wall, 0.5))}};
}

} // namespace

int main(int argc, char** argv) {
    CLI::App app{"Oriented-particle solver, soft scenes and shatter-car frame times on one core."};
    int frames = 240, repeats = 3, steps = 20, sheetCells = 70, sheetIterations = 3, sheetSubsteps = 4,
        sheetRotationIterations = shatter::oriented::SolverSettings{}.rotationIterations, curtainCells = 50;
    // The sheet of 4 plain sweeps of 0.3 (main before this change, bit for bit):
    // --sheet-iterations 4 --sheet-stiffness 0 --sheet-chebyshev-radius 0.
    double sheetSleepSpeed = 0.01, sheetStiffness = 0.33, sheetChebyshev = 0.65;
    bool sheetPortable = false;
    std::vector<std::string> scenes{"soft", "soft-no-self-contact", "sheet", "curtain", "car"};
    app.add_option("--frames", frames, "frames per run (60 Hz)")->capture_default_str()->check(CLI::PositiveNumber);
    app.add_option("--repeats", repeats, "runs; quantiles are over all of them")->capture_default_str()->check(CLI::PositiveNumber);
    app.add_option("--solver-steps", steps, "soft steps per particle-rate run")->capture_default_str()->check(CLI::PositiveNumber);
    app.add_option("--sheet-cells", sheetCells, "the soft sheet has this many squared quads")
        ->capture_default_str()->check(CLI::PositiveNumber);
    app.add_option("--sheet-iterations", sheetIterations, "the sheet's projection sweeps per step")
        ->capture_default_str()->check(CLI::PositiveNumber);
    app.add_option("--sheet-rotation-iterations", sheetRotationIterations,
                   "the sheet's rotation-fit iterations per group projection, at most (SolverSettings::rotationIterations)")
        ->capture_default_str()->check(CLI::PositiveNumber);
    app.add_option("--sheet-substeps-per-step", sheetSubsteps,
                   "the sheet's contacts are found once every this many substeps away from moving bodies and while "
                   "slow enough (SolverSettings::substepsPerStep; the solver takes every substep: the same sheet)")
        ->capture_default_str()->check(CLI::PositiveNumber);
    app.add_flag("--sheet-portable", sheetPortable,
                 "the sheet's solver on the portable path (SSE2) even where AVX2 is there (SolverSettings::simdPath; the same bits)");
    app.add_option("--sheet-stiffness", sheetStiffness, "the sheet's stiffness per sweep (0: a whole step's of 4 sweeps of 0.3 over --sheet-iterations)")
        ->capture_default_str()->check(CLI::Range(0.0, 1.0));
    app.add_option("--sheet-chebyshev-radius", sheetChebyshev, "the sheet's Chebyshev acceleration (SolverSettings::chebyshevRadius)")
        ->capture_default_str()->check(CLI::Range(0.0, shatter::oriented::kMaxChebyshevRadius));
    app.add_option("--sheet-sleep-speed", sheetSleepSpeed, "m/s: the sheet sleeps after half a second under it (0: never)")
        ->capture_default_str()->check(CLI::NonNegativeNumber);
    app.add_option("--curtain-cells", curtainCells, "the curtain has this many squared quads")
        ->capture_default_str()->check(CLI::PositiveNumber);
    app.add_option("--scenes", scenes, "scenes to run (for profiling one of them)")
        ->capture_default_str()->check(CLI::IsMember({"soft", "soft-no-self-contact", "sheet", "curtain", "car"}));
    bool gjkSoftBoxContacts = false;
    app.add_flag("--gjk-soft-box-contacts", gjkSoftBoxContacts,
                 "soft bodies against boxes take Bullet's GJK and EPA instead of the exact one-point contact (HullPairContacts::softBoxContacts)");
    std::string pictures;
    app.add_option("--pictures", pictures, "write each soft scene's last frame (first run) as DIR/<scene>.png");
    CLI11_PARSE(app, argc, argv);
    if (!pictures.empty()) std::filesystem::create_directories(pictures);
    const auto pictureFile = [&](const std::string& scene) {
        return pictures.empty() ? std::string() : (std::filesystem::path(pictures) / (scene + ".png")).string();
    };
    if (gjkSoftBoxContacts) shatter::hullPairContacts().softBoxContacts = false;
    const auto wanted = [&](const std::string& scene) { return std::ranges::find(scenes, scene) != scenes.end(); };
    try {
        nlohmann::ordered_json report;
        if (wanted("soft"))
            report["soft"] =
                softReport("shatter-soft", [](Scene& s) { shatter::demo::buildSoftScene(s, {}); }, frames, repeats,
                           pictureFile("soft"));
        if (wanted("soft-no-self-contact")) {
            // The same scene without self-contact: what colliding a body's own primitives costs.
            shatter::demo::SoftScene noSelf;
            noSelf.jelly.solver.selfContact = noSelf.tyre.solver.selfContact = false;
            report["soft_without_self_contact"] = softReport(
                "shatter-soft, no self-contact", [&](Scene& s) { shatter::demo::buildSoftScene(s, noSelf); }, frames,
                repeats, pictureFile("soft-no-self-contact"));
        }
        if (wanted("sheet"))
            report["sheet"] = softReport("sheet", [&](Scene& s) { buildSheetScene(s, sheetCells, sheetIterations, sheetRotationIterations, sheetSubsteps, sheetSleepSpeed,
                                                                                sheetPortable ? shatter::oriented::SimdPath::Portable
                                                                                              : shatter::oriented::fastestSimdPath(), sheetStiffness, sheetChebyshev); }, frames, repeats,
                                         pictureFile("sheet"));
        if (wanted("curtain"))
            report["curtain"] = softReport("curtain (shatter-tear's, not tearing)",
                                           [&](Scene& s) { buildCurtainScene(s, curtainCells); }, frames, repeats,
                                           pictureFile("curtain"));
        if (wanted("car")) {
            std::mt19937_64 rng(1);
            shatter::geometry::PhysicalMeshSettings shell;
            shell.thickness = 0.01;
            shell.density = 1500;
            const auto object =
                shatter::geometry::buildPhysicalObject(shatter::demo::carShell().parse("car.obj"), shell);
            std::vector<double> rates;
            Timed car;
            for (int r = 0; r < repeats; ++r) {
                rates.push_back(particleIterationsPerSecond(object.bodies[0], steps, rng));
                Scene scene(1);
                shatter::demo::ThrownBall ball{12.0, 20.0, 0.12};
                shatter::demo::buildCarScene(scene, ball, 30);
                runFrames(scene, frames, car, [](const std::vector<shatter::Event>& events) {
                    return std::any_of(events.begin(), events.end(), [](const shatter::Event& e) {
                        return e.type == shatter::EventType::BodyDented;
                    });
                });
            }
            std::vector<double> all = car.wall;
            all.insert(all.end(), car.specialWall.begin(), car.specialWall.end());
            report["car"] = {{"primitives", object.bodies[0].primitives.size()},
                             {"particle_iterations_per_second_median", quantile(rates, 0.5)},
                             {"frame_ms", stats(all)},
                             {"rigid_frame_ms", stats(car.wall)},
                             {"plastic_frames", car.specialWall.size()},
                             {"plastic_frame_ms", stats(car.specialWall)}};
        }
        report["frames"] = frames;
        report["repeats"] = repeats;
        std::cout << report.dump(2) << "\n";
    } catch (const std::exception& e) {
        std::cerr << "shatter-bench-oriented: error: " << e.what() << "\n";
        return 1;
    }
    return 0;
}
