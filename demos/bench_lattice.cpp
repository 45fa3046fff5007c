// shatter-bench-lattice: a breakable-body scene of the demos (wall, table or noise, exactly as
// shatter-wall/-table/-noise build it) timed frame by frame and phase by phase: Bullet's own
// phases from its profile zones (AABBs, broadphase, narrowphase, islands, solver, integration)
// and the lattice's (impacts, assembly, CG, breaking, fragment creation, resting), with the
// median, 99th percentile and worst frame. Writes DIR/<scene>_seed<S>.csv (one row per frame)
// and .png (the frames stacked by phase, with the 16.7 and 33.3 ms lines); the last stdout
// line is the result as JSON. --cholesky also solves every analysed system with Eigen's
// SimplicialLDLT (timed apart, not counted in the frames).
#include "demos/LatticeScenes.h"
#include "demos/bench/BulletZones.h"
#include "demos/bench/ContactOptions.h"
#include "demos/bench/FrameStats.h"
#include "demos/runner/OutputDirectory.h"

#include <shatter/bullet_ext/Plugin.h>
#include <shatter/bullet_ext/VisualBody.h>
#include <shatter/bullet_ext/lattice/LatticeSystem.h>
#include <shatter/plugin/common/InputError.h>

#include <Eigen/SparseCholesky>
#include <btBulletDynamicsCommon.h>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <ctime>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>
#include <variant>
#include <map>

namespace {

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

// This thread's CPU time (ms): unlike the wall clock, it does not count the time other
// processes of a loaded machine take the core away, so before/after comparisons hold.
double threadCpuMs() {
    timespec t{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return 1e3 * double(t.tv_sec) + 1e-6 * double(t.tv_nsec);
}

struct Options {
    std::string scene = "wall";
    int frames = 240;
    int substeps = 4;
    std::uint64_t seed = 1;
    std::string out = "out/bench_lattice";
    std::string json;
    bool cholesky = false;
    int pairKinds = 0; // print the overlapping pairs by shape kind after this frame (0: never)
};

// The broadphase's overlapping pairs by the two shapes' kinds (and whether one is static).
void printPairKinds(btDiscreteDynamicsWorld& world, int frame) {
    std::map<std::string, int> kinds;
    btOverlappingPairCache* cache = world.getPairCache();
    for (int i = 0; i < cache->getNumOverlappingPairs(); ++i) {
        const btBroadphasePair& p = cache->getOverlappingPairArray()[i];
        const auto* a = static_cast<btCollisionObject*>(p.m_pProxy0->m_clientObject);
        const auto* b = static_cast<btCollisionObject*>(p.m_pProxy1->m_clientObject);
        // Debris (DebrisSettings) are marked: their pairs are with what is not debris.
        const auto kind = [](const btBroadphaseProxy* p, const btCollisionObject* o) {
            return std::string(o->getCollisionShape()->getName()) +
                   (p->m_collisionFilterGroup & btBroadphaseProxy::DebrisFilter ? " debris" : "");
        };
        std::string ka = kind(p.m_pProxy0, a), kb = kind(p.m_pProxy1, b);
        if (ka > kb) std::swap(ka, kb);
        kinds[ka + " / " + kb + (a->isStaticObject() || b->isStaticObject() ? " (one static)" : "")]++;
    }
    std::fprintf(stderr, "overlapping pairs after frame %d:\n", frame);
    for (const auto& [kind, n] : kinds) std::fprintf(stderr, "%8d %s\n", n, kind.c_str());
}

// Every system the lattice analyses, solved again by Eigen's SimplicialLDLT and by CG from the
// same warm start (timed apart from the frames), through the lattice system's analysis observer.
struct CholeskyComparison {
    int solves = 0;
    double choleskySeconds = 0.0;   // assembly of the sparse matrix, factorisation and solve
    double cgSeconds = 0.0;         // CG on the same systems from the same warm start
    double largestDifference = 0.0; // max ‖λ_CG − λ_LDLT‖ / ‖λ_LDLT‖
    double cpuMs = 0.0;             // thread CPU time of the comparisons (ms)

    void compare(const shatter::lattice::Lattice& lattice, shatter::lattice::LatticePiece& piece,
                 const Eigen::VectorXd& loads, const Eigen::Vector3d& omega, const shatter::LatticeSettings& settings) {
        const double cpuStart = threadCpuMs();
        compareSolves(lattice, piece, loads, omega, settings);
        cpuMs += threadCpuMs() - cpuStart;
    }
    void compareSolves(const shatter::lattice::Lattice& lattice, shatter::lattice::LatticePiece& piece,
                       const Eigen::VectorXd& loads, const Eigen::Vector3d& omega, const shatter::LatticeSettings& settings) {
        const auto& system = piece.constraintSystem(lattice);
        if (system.rowCount() == 0) return;
        const Eigen::VectorXd b = system.rightHandSide(loads, omega);
        auto t = Clock::now();
        Eigen::VectorXd cg = piece.lambda;
        system.solve(b, cg, settings.analysis.solver);
        cgSeconds += 1e-3 * msSince(t);
        t = Clock::now();
        Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(system.assemble());
        const Eigen::VectorXd direct = ldlt.solve(b);
        choleskySeconds += 1e-3 * msSince(t);
        ++solves;
        if (ldlt.info() == Eigen::Success && direct.norm() > 0)
            largestDifference = std::max(largestDifference, (cg - direct).norm() / direct.norm());
    }
    double seconds() const { return choleskySeconds + cgSeconds; }
};

// Bullet's zones, grouped into the phases reported (each inclusive of what it calls).
const std::vector<std::pair<const char*, std::vector<const char*>>> kBulletPhases = {
    {"bullet_aabbs", {"updateAabbs"}},
    {"bullet_broadphase", {"calculateOverlappingPairs"}},
    {"bullet_narrowphase", {"dispatchAllCollisionPairs"}},
    {"bullet_islands", {"calculateSimulationIslands", "updateActivationState"}},
    {"bullet_solver", {"solveConstraints"}},
    {"bullet_integrate", {"predictUnconstraintMotion", "createPredictiveContacts", "integrateTransforms"}},
};

struct Run {
    shatter::demo::Scene scene;
    std::vector<shatter::LatticeBody*> bodies;
    CholeskyComparison cholesky;
    explicit Run(std::uint64_t seed) : scene(seed) {}
};

std::unique_ptr<Run> buildRun(const Options& o, const std::variant<shatter::demo::WallOptions, shatter::demo::TableOptions,
                                                                    shatter::demo::NoiseOptions>& scene) {
    auto run = std::make_unique<Run>(o.seed);
    run->bodies = std::visit([&](const auto& s) { return shatter::demo::buildScene(run->scene, s, "shatter-bench-lattice"); },
                             scene);
    if (o.cholesky)
        run->scene.plugin().lattices().setAnalysisObserver(
            [c = &run->cholesky](const auto& lattice, auto& piece, const auto& loads, const auto& omega, const auto& s) {
                c->compare(lattice, piece, loads, omega, s);
            });
    return run;
}

// One frame: stepped as the demo runner steps it, timed by phase into the table's next row.
void stepFrame(Run& run, const Options& o, shatter::bench::BulletZones& zones, shatter::bench::FrameTable& table) {
    auto& lattices = run.scene.plugin().lattices();
    lattices.resetTiming();
    zones.take();
    const double comparedBefore = run.cholesky.seconds(), comparedCpuBefore = run.cholesky.cpuMs;
    const btScalar fixed = btScalar(1.0 / (60.0 * o.substeps));
    const auto start = Clock::now();
    const double cpuStart = threadCpuMs();
    run.scene.world().stepSimulation(fixed * btScalar(o.substeps) * btScalar(1 + 1e-5), o.substeps, fixed);
    const double cpu = threadCpuMs() - cpuStart - (run.cholesky.cpuMs - comparedCpuBefore);
    const double total = msSince(start) - 1e3 * (run.cholesky.seconds() - comparedBefore);
    auto spent = zones.take();
    const auto& t = lattices.timing();
    table.beginFrame();
    double bullet = 0.0;
    for (const auto& [phase, names] : kBulletPhases)
        for (const char* name : names) {
            table.addTime(phase, spent[name]);
            bullet += spent[name];
        }
    const double lattice = 1e3 * (t.impacts + t.assembly + t.solve + t.breaking + t.fragments + t.resting);
    const double shatter = spent["updateActions"]; // Shatter runs as Bullet's action
    table.addTime("bullet_other", std::max(0.0, total - bullet - shatter));
    table.addTime("lattice_impacts", 1e3 * t.impacts);
    table.addTime("lattice_assembly", 1e3 * t.assembly);
    table.addTime("lattice_cg", 1e3 * t.solve);
    table.addTime("lattice_breaking", 1e3 * t.breaking);
    table.addTime("lattice_fragments", 1e3 * t.fragments);
    table.addTime("lattice_resting", 1e3 * t.resting);
    table.addTime("shatter_other", std::max(0.0, shatter - lattice - 1e3 * (run.cholesky.seconds() - comparedBefore)));
    // What the frame had to work on.
    int pieces = 0, frozen = 0, awake = 0;
    for (const auto* b : run.bodies) pieces += b->pieceCount(), frozen += b->frozenPieceCount();
    double fastest = 0.0, kinetic = 0.0;
    for (const auto& b : run.scene.plugin().bodies()) {
        const btRigidBody& r = b->rigidBody();
        if (r.getInvMass() == 0) continue;
        awake += r.isActive();
        const double v = double(r.getLinearVelocity().length());
        fastest = std::max(fastest, v);
        const btVector3 w = r.getAngularVelocity();
        const btVector3 Iw = r.getInvInertiaTensorWorld().inverse() * w;
        kinetic += 0.5 * v * v / double(r.getInvMass()) + 0.5 * double(w.dot(Iw));
    }
    btDispatcher& dispatcher = *run.scene.world().getDispatcher();
    int points = 0;
    for (int m = 0; m < dispatcher.getNumManifolds(); ++m) points += dispatcher.getManifoldByIndexInternal(m)->getNumContacts();
    table.setCount("cpu_ms", cpu);
    table.setCount("pieces", pieces);
    table.setCount("awake", awake);
    table.setCount("frozen", frozen);
    table.setCount("pairs", run.scene.world().getPairCache()->getNumOverlappingPairs());
    table.setCount("manifolds", dispatcher.getNumManifolds());
    table.setCount("contact_points", points);
    table.setCount("links_broken", t.linksBroken);
    table.setCount("fragments_created", t.fragmentsCreated);
    table.setCount("cg_iterations", t.iterations);
    table.setCount("speeds_limited", t.speedsLimited);
    table.setCount("fastest_piece_m_s", fastest);
    table.setCount("kinetic_energy_j", kinetic);
}

nlohmann::ordered_json frameRow(const shatter::bench::FrameTable& table, int f) {
    nlohmann::ordered_json row;
    row["frame"] = f + 1;
    row["total_ms"] = table.total(f);
    for (const auto& p : table.phases()) row[p + "_ms"] = table.time(f, p);
    for (const char* c : {"cpu_ms", "pieces", "awake", "pairs", "contact_points", "links_broken", "fragments_created",
                          "cg_iterations", "fastest_piece_m_s"})
        row[c] = table.count(f, c);
    return row;
}

} // namespace

int main(int argc, char** argv) {
    CLI::App app{"shatter-bench-lattice: a breakable-body scene of the demos timed per frame and phase."};
    Options o;
    shatter::demo::WallOptions wall;
    shatter::demo::TableOptions table;
    shatter::demo::NoiseOptions noise;
    app.add_option("--scene", o.scene, "wall, table or noise (as shatter-wall, -table, -noise build them)")
        ->check(CLI::IsMember({"wall", "table", "noise"}))
        ->capture_default_str();
    app.add_option("--frames", o.frames, "frames of 1/60 s")->check(CLI::Range(1, 100000))->capture_default_str();
    app.add_option("--substeps", o.substeps, "internal steps per frame")->check(CLI::Range(1, 100))->capture_default_str();
    app.add_option("--seed", o.seed, "the scene's seed (mesh jitter, damage spreading)")->capture_default_str();
    app.add_option("--out", o.out, "directory for <scene>_seed<S>.csv and .png")->capture_default_str();
    app.add_option("--json", o.json, "also write the result to this file");
    app.add_flag("--cholesky", o.cholesky, "also solve every system with SimplicialLDLT and compare with CG");
    app.add_option("--pair-kinds", o.pairKinds, "print the overlapping pairs by shape kind after this frame");
    app.add_flag("!--no-freeze", wall.lattice.freeze, "let resting fragments only sleep instead of freezing them");
    app.add_option("--tets", wall.lattice.tets, "TetGen mesh (PATH.ele) instead of the scene's built-in one");
    shatter::demo::addDebrisOptions(app, wall.lattice);
    shatter::demo::addFragmentBudgetOption(app, wall.lattice);
    shatter::demo::addKeepPairsOption(app, wall.lattice);
    app.add_option("--anchor", wall.lattice.anchor, "fixed tets, as shatter-wall and shatter-table take it (e.g. contact:0.03 for a statue; default: each scene's own, bottom for the wall, none for the table; the noise scene ignores it)");
    shatter::bench::addContactOptions(app);
    CLI11_PARSE(app, argc, argv);
    try {
        table.lattice.freeze = noise.lattice.freeze = wall.lattice.freeze;
        table.lattice.tets = noise.lattice.tets = wall.lattice.tets;
        for (auto* l : {&table.lattice, &noise.lattice}) {
            l->debris = wall.lattice.debris;
            l->debrisSize = wall.lattice.debrisSize;
            l->debrisBudget = wall.lattice.debrisBudget;
            l->debrisLifetime = wall.lattice.debrisLifetime;
            l->debrisRest = wall.lattice.debrisRest;
            l->minFragmentSize = wall.lattice.minFragmentSize;
            l->fragmentBudget = wall.lattice.fragmentBudget;
            l->keepPairs = wall.lattice.keepPairs;
        }
        // The table rests on its legs (anchor "none"): it takes the wall's anchor only when one is given.
        if (app.count("--anchor") > 0) table.lattice.anchor = wall.lattice.anchor;
        std::variant<shatter::demo::WallOptions, shatter::demo::TableOptions, shatter::demo::NoiseOptions> scene = wall;
        if (o.scene == "table") scene = table;
        if (o.scene == "noise") scene = noise;
        shatter::demo::prepareOutputDirectory(o.out);
        auto run = buildRun(o, scene);
        shatter::bench::BulletZones zones;
        shatter::bench::FrameTable frames;
        for (int i = 0; i < o.frames; ++i) {
            stepFrame(*run, o, zones, frames);
            if (i + 1 == o.pairKinds) printPairKinds(run->scene.world(), i + 1);
        }
        const std::string stem = o.out + "/" + o.scene + "_seed" + std::to_string(o.seed);
        frames.writeCsv(stem + ".csv");
        shatter::bench::plotFrames(frames, "shatter-bench-lattice --scene " + o.scene + " --seed " + std::to_string(o.seed),
                                   stem + ".png");

        nlohmann::ordered_json out;
        out["scene"] = {{"name", o.scene}, {"seed", o.seed}, {"frames", o.frames}, {"substeps", o.substeps}};
        int tets = 0, links = 0, broken = 0, fragments = 0, frozen = 0, debris = 0, debrisRemoved = 0;
        double massInitial = 0, massFinal = 0, massRemoved = 0;
        for (const auto* b : run->bodies) {
            tets += b->tetCount(), links += b->linkCount(), broken += b->brokenLinkCount();
            fragments += b->pieceCount(), frozen += b->frozenPieceCount();
            massInitial += b->initialMass(), massFinal += b->currentMass(), massRemoved += b->removedDebrisMass();
            debrisRemoved += b->removedDebrisCount();
            for (const auto& p : b->pieces()) debris += p.debris;
        }
        // Fragments: every piece made, the debris removed by their budget or lifetime included.
        out["result"] = {{"tets", tets},
                         {"links", links},
                         {"links_broken", broken},
                         {"fragments", fragments + debrisRemoved},
                         {"fragments_frozen", frozen},
                         {"debris", debris},
                         {"debris_removed", debrisRemoved},
                         {"mass_initial", massInitial},
                         {"mass_final", massFinal},
                         {"mass_removed_debris", massRemoved}};
        out["phases"] = frames.summary();
        std::vector<double> cpu;
        for (int f = 0; f < frames.frames(); ++f) cpu.push_back(frames.count(f, "cpu_ms"));
        out["cpu"] = {{"median_ms", shatter::bench::percentile(cpu, 0.5)},
                      {"p99_ms", shatter::bench::percentile(cpu, 0.99)},
                      {"worst_ms", *std::max_element(cpu.begin(), cpu.end())}};
        const int worst = out["phases"]["frame"]["worst_frame"].get<int>() - 1;
        out["worst_frame"] = frameRow(frames, worst);
        for (int f = 0; f < frames.frames(); ++f)
            if (frames.count(f, "links_broken") > 0) {
                out["first_break_frame"] = frameRow(frames, f);
                break;
            }
        if (o.cholesky)
            out["cg_vs_cholesky"] = {{"systems", run->cholesky.solves},
                                     {"cg_ms_total", 1e3 * run->cholesky.cgSeconds},
                                     {"cholesky_ms_total", 1e3 * run->cholesky.choleskySeconds},
                                     {"cholesky_over_cg", run->cholesky.cgSeconds > 0
                                                              ? run->cholesky.choleskySeconds / run->cholesky.cgSeconds
                                                              : 0.0},
                                     {"largest_relative_difference", run->cholesky.largestDifference}};
        const auto& f = out["phases"]["frame"];
        std::printf("shatter-bench-lattice --scene %s --seed %llu: %d tets, %d frames: median %.2f ms, p99 %.2f ms, worst "
                    "%.2f ms (frame %d); thread CPU median %.2f ms, p99 %.2f ms, worst %.2f ms; %d fragments, %d links broken; "
                    "%s.csv, %s.png\n",
                    o.scene.c_str(), (unsigned long long)o.seed, tets, o.frames, f["median_ms"].get<double>(),
                    f["p99_ms"].get<double>(), f["worst_ms"].get<double>(), worst + 1, out["cpu"]["median_ms"].get<double>(),
                    out["cpu"]["p99_ms"].get<double>(), out["cpu"]["worst_ms"].get<double>(), fragments + debrisRemoved, broken, stem.c_str(),
                    stem.c_str());
        if (!o.json.empty()) std::ofstream(o.json) << out.dump(2) << "\n";
        std::printf("%s\n", out.dump().c_str());
    } catch (const std::exception& e) {
        std::fprintf(stderr, "shatter-bench-lattice: error: %s\n", e.what());
        return 1;
    }
    return 0;
}
