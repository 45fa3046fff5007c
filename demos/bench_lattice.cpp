// shatter-bench-lattice: the wall scene of shatter-wall (4,080 tets, a 400 kg ball at 9 m/s),
// timed per frame: Bullet's own step and the lattice analysis by phase (impacts, assembly, CG,
// breaking, fragment creation), with medians and the worst frame, the frame where the wall
// shatters reported on its own. Every system the CG solves is also solved by Eigen's sparse
// Cholesky (SimplicialLDLT) in the same run (timed apart, not counted in the frames), and the
// ratio of the two is printed. The last stdout line is the result as JSON.
#include <shatter/bullet_ext/lattice/LatticeBody.h>
#include <shatter/bullet_ext/lattice/LatticeSystem.h>
#include <shatter/bullet_ext/Plugin.h>
#include <shatter/bullet_ext/VisualBody.h>
#include <shatter/plugin/common/InputError.h>
#include <shatter/plugin/lattice/TetGenReader.h>
#include <shatter/plugin/lattice/TetGenerators.h>

#include <btBulletDynamicsCommon.h>

#include <Eigen/SparseCholesky>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>
#include <vector>

namespace {

struct Options {
    int frames = 240;
    int substeps = 4;
    double ballSpeed = 9.0, ballMass = 400.0, ballRadius = 0.25;
    std::uint64_t seed = 1;
    std::string tets;
    bool cholesky = true;
    bool freeze = true;
    bool trace = false;
    std::string json;
};

// Every system the lattice analyses, solved again by Eigen's SimplicialLDLT and by CG from the
// same warm start (timed apart from the frames), through the lattice system's analysis observer.
struct CholeskyComparison {
    int solves = 0;
    double choleskySeconds = 0.0;   // assembly of the sparse matrix, factorisation and solve
    double cgSeconds = 0.0;         // CG on the same systems from the same warm start
    double largestDifference = 0.0; // max ‖λ_CG − λ_LDLT‖ / ‖λ_LDLT‖

    void compare(const shatter::lattice::Lattice& lattice, shatter::lattice::LatticePiece& piece,
                 const Eigen::VectorXd& loads, const Eigen::Vector3d& omega, const shatter::LatticeSettings& settings) {
        const auto& system = piece.constraintSystem(lattice);
        if (system.rowCount() == 0) return;
        const Eigen::VectorXd b = system.rightHandSide(loads, omega);
        auto t = std::chrono::steady_clock::now();
        Eigen::VectorXd cg = piece.lambda;
        system.solve(b, cg, settings.analysis.solver);
        cgSeconds += secondsSince(t);
        t = std::chrono::steady_clock::now();
        Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(system.assemble());
        const Eigen::VectorXd direct = ldlt.solve(b);
        choleskySeconds += secondsSince(t);
        ++solves;
        if (ldlt.info() == Eigen::Success && direct.norm() > 0)
            largestDifference = std::max(largestDifference, (cg - direct).norm() / direct.norm());
    }

    static double secondsSince(std::chrono::steady_clock::time_point t) {
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
    }
};

// One frame's milliseconds by phase.
struct FrameTimes {
    double total = 0, bullet = 0, lattice = 0, impacts = 0, assembly = 0, cg = 0, breaking = 0, fragments = 0, resting = 0;
    int pieces = 0, linksBroken = 0, iterations = 0, awake = 0;
    int frozen = 0, thawed = 0; // pieces frozen at the frame's end; pieces woken in it
};

// The world of an application, as the demo runner builds it.
struct World {
    btDefaultCollisionConfiguration config;
    btCollisionDispatcher dispatcher{&config};
    btDbvtBroadphase broadphase;
    btSequentialImpulseConstraintSolver solver;
    btDiscreteDynamicsWorld world{&dispatcher, &broadphase, &solver, &config};
    btStaticPlaneShape groundShape{btVector3(0, 1, 0), 0};
    btRigidBody ground{0, nullptr, &groundShape};
    btSphereShape ballShape;
    std::unique_ptr<btRigidBody> ball;
    std::unique_ptr<shatter::Plugin> plugin;
    shatter::LatticeBody* wall = nullptr;
    CholeskyComparison cholesky;

    explicit World(const Options& o) : ballShape(btScalar(o.ballRadius)) {
        world.setGravity(btVector3(0, btScalar(-9.81), 0));
        // As demos/runner/Scene.cpp: two friction directions per contact (resting bodies do not
        // creep), and split impulses only (demos/LatticeDemo.h useSplitImpulsesOnly).
        world.getSolverInfo().m_solverMode |= SOLVER_USE_2_FRICTION_DIRECTIONS;
        world.getSolverInfo().m_splitImpulse = 1;
        world.getSolverInfo().m_splitImpulsePenetrationThreshold = 0;
        ground.setFriction(0.8f);
        world.addRigidBody(&ground);
        plugin = std::make_unique<shatter::Plugin>(world);
        shatter::lattice::TetMesh mesh;
        if (o.tets.empty()) {
            shatter::lattice::GeneratorOptions g;
            g.name = "wall";
            g.jitter = 0.15;
            g.seed = o.seed;
            mesh = shatter::lattice::tetBox({1.7, 1.0, 0.4}, {17, 10, 4}, g);
        } else {
            mesh = shatter::lattice::readTetGen(o.tets);
        }
        double lowest = INFINITY, front = -INFINITY, top = -INFINITY;
        for (const auto& n : mesh.nodes) lowest = std::min(lowest, n.y()), front = std::max(front, n.z()), top = std::max(top, n.y());
        shatter::LatticeSettings s;
        s.name = "wall";
        s.seed = o.seed;
        s.fixedTets = shatter::lattice::tetsWithFaceOnPlane(mesh, {0, 1, 0}, lowest, 1e-6);
        s.rest.freezeAtRest = o.freeze;
        wall = &plugin->addLatticeBody(mesh, s, btTransform(btQuaternion::getIdentity(), btVector3(0, btScalar(-lowest), 0)));
        btVector3 inertia;
        ballShape.calculateLocalInertia(btScalar(o.ballMass), inertia);
        ball = std::make_unique<btRigidBody>(btScalar(o.ballMass), nullptr, &ballShape, inertia);
        ball->setWorldTransform(btTransform(btQuaternion::getIdentity(),
                                            btVector3(0, btScalar(0.45 * (top - lowest)), btScalar(front + o.ballRadius + 0.3))));
        ball->setLinearVelocity(btVector3(0, 0, btScalar(-o.ballSpeed)));
        ball->setFriction(0.5f);
        world.addRigidBody(ball.get());
        if (o.cholesky)
            plugin->lattices().setAnalysisObserver(
                [this](const auto& lattice, auto& piece, const auto& loads, const auto& omega, const auto& s) {
                    cholesky.compare(lattice, piece, loads, omega, s);
                });
    }
    ~World() {
        plugin.reset();
        world.removeRigidBody(ball.get());
        world.removeRigidBody(&ground);
    }
};

double median(std::vector<double> v) {
    if (v.empty()) return 0;
    std::sort(v.begin(), v.end());
    return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

FrameTimes stepFrame(World& w, const Options& o) {
    auto& lattices = w.plugin->lattices();
    lattices.resetTiming();
    const double comparedBefore = w.cholesky.choleskySeconds + w.cholesky.cgSeconds;
    const btScalar fixed = btScalar(1.0 / (60.0 * o.substeps));
    const auto start = std::chrono::steady_clock::now();
    w.world.stepSimulation(fixed * btScalar(o.substeps) * btScalar(1 + 1e-5), o.substeps, fixed);
    const double wall = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    const auto& t = lattices.timing();
    FrameTimes f;
    // The Cholesky comparison runs inside the step; it is not part of the frame.
    f.total = wall - 1e3 * (w.cholesky.choleskySeconds + w.cholesky.cgSeconds - comparedBefore);
    f.impacts = 1e3 * t.impacts;
    f.assembly = 1e3 * t.assembly;
    f.cg = 1e3 * t.solve;
    f.breaking = 1e3 * t.breaking;
    f.fragments = 1e3 * t.fragments;
    f.resting = 1e3 * t.resting;
    f.lattice = f.impacts + f.assembly + f.cg + f.breaking + f.fragments + f.resting;
    f.bullet = f.total - f.lattice;
    f.pieces = w.wall->pieceCount();
    for (const auto& b : w.plugin->bodies()) f.awake += b->rigidBody().isActive() && b->rigidBody().getInvMass() > 0;
    f.frozen = w.wall->frozenPieceCount();
    f.thawed = t.thawed;
    f.linksBroken = t.linksBroken;
    f.iterations = t.iterations;
    return f;
}

nlohmann::json phaseStats(const std::vector<FrameTimes>& frames, double FrameTimes::*field) {
    std::vector<double> v;
    for (const auto& f : frames) v.push_back(f.*field);
    return {{"median_ms", median(v)}, {"worst_ms", v.empty() ? 0.0 : *std::max_element(v.begin(), v.end())}};
}

nlohmann::json frameJson(const FrameTimes& f, int index) {
    return {{"frame", index},           {"total_ms", f.total},     {"bullet_ms", f.bullet},
            {"lattice_ms", f.lattice},  {"impacts_ms", f.impacts}, {"assembly_ms", f.assembly},
            {"cg_ms", f.cg},            {"breaking_ms", f.breaking}, {"fragments_ms", f.fragments},
            {"resting_ms", f.resting},
            {"links_broken", f.linksBroken}, {"pieces", f.pieces}, {"awake", f.awake},
            {"frozen", f.frozen}, {"thawed", f.thawed}, {"cg_iterations", f.iterations}};
}

} // namespace

int main(int argc, char** argv) {
    CLI::App app{"shatter-bench-lattice: the shatter-wall scene timed per frame, CG against sparse Cholesky."};
    Options o;
    app.add_option("--frames", o.frames, "frames of 1/60 s")->check(CLI::Range(1, 100000));
    app.add_option("--substeps", o.substeps, "internal steps per frame")->check(CLI::Range(1, 100));
    app.add_option("--ball-speed", o.ballSpeed, "m/s");
    app.add_option("--ball-mass", o.ballMass, "kg");
    app.add_option("--seed", o.seed, "mesh jitter and damage spreading seed");
    app.add_option("--tets", o.tets, "TetGen mesh (PATH.ele) instead of the built-in wall");
    app.add_flag("!--no-cholesky", o.cholesky, "skip the SimplicialLDLT comparison");
    app.add_flag("!--no-freeze", o.freeze, "resting fragments only sleep (Bullet's islands), are not frozen");
    app.add_option("--json", o.json, "also write the result to this file");
    app.add_flag("--trace", o.trace, "print every frame's times and motion to stderr");
    CLI11_PARSE(app, argc, argv);
    try {
        if (!(std::isfinite(o.ballSpeed) && o.ballSpeed >= 0)) throw shatter::InputError("--ball-speed must be finite and >= 0 m/s");
        if (!(std::isfinite(o.ballMass) && o.ballMass > 0)) throw shatter::InputError("--ball-mass must be finite and > 0 kg");
        World w(o);
        std::vector<FrameTimes> frames;
        int shatterFrame = -1;
        for (int i = 1; i <= o.frames; ++i) {
            frames.push_back(stepFrame(w, o));
            if (shatterFrame < 0 && frames.back().linksBroken > 0) shatterFrame = i;
            if (o.trace && i == o.frames) {
                // The last frame: every body's place, box (without Bullet's 2 cm breaking
                // threshold), motion and activation state (1 awake, 2 asleep, 3 ready to sleep).
                for (const auto& b : w.plugin->bodies()) {
                    const btRigidBody& r = b->rigidBody();
                    btVector3 lo, hi;
                    r.getCollisionShape()->getAabb(r.getWorldTransform(), lo, hi);
                    const btVector3 c = r.getCenterOfMassPosition();
                    std::fprintf(stderr, "body %s type %d at %.3f %.3f %.3f box %.3f %.3f %.3f v %.3f w %.3f state %d\n",
                                 b->name().c_str(), r.getCollisionShape()->getShapeType(), c.x(), c.y(), c.z(),
                                 hi.x() - lo.x(), hi.y() - lo.y(), hi.z() - lo.z(), r.getLinearVelocity().length(),
                                 r.getAngularVelocity().length(), r.getActivationState());
                }
            }
            if (o.trace) {
                int moving = 0;
                double fastest = 0, spin = 0;
                for (const auto& b : w.plugin->bodies()) {
                    const double v = b->rigidBody().getLinearVelocity().length();
                    moving += v > 0.05;
                    fastest = std::max(fastest, v);
                    spin = std::max(spin, double(b->rigidBody().getAngularVelocity().length()));
                }
                // Loose pieces by activation state (Bullet sleeps an island only when none is
                // awake), broadphase pairs (what Bullet's islands and narrowphase run over) and
                // manifolds with contact points (pairs that really touch).
                int touching = 0, states[6] = {0, 0, 0, 0, 0, 0};
                for (const auto& b : w.plugin->bodies())
                    if (b->rigidBody().getInvMass() > 0) ++states[std::clamp(b->rigidBody().getActivationState(), 0, 5)];
                for (int m = 0; m < w.dispatcher.getNumManifolds(); ++m)
                    touching += w.dispatcher.getManifoldByIndexInternal(m)->getNumContacts() > 0;
                std::fprintf(stderr,
                             "awake %d ready %d asleep %d moving %d fastest %.3f spin %.3f ball %.3f state %d pairs %d "
                             "touching %d | %s\n",
                             states[1], states[3], states[2], moving, fastest, spin, w.ball->getLinearVelocity().length(),
                             w.ball->getActivationState(), w.world.getPairCache()->getNumOverlappingPairs(), touching,
                             frameJson(frames.back(), i).dump().c_str());
            }
        }
        nlohmann::ordered_json out;
        out["scene"] = {{"tets", w.wall->tetCount()}, {"links", w.wall->linkCount()}, {"frames", o.frames},
                        {"substeps", o.substeps}, {"ball_speed", o.ballSpeed}, {"ball_mass", o.ballMass},
                        {"seed", o.seed}, {"freeze", o.freeze}};
        out["result"] = {{"links_broken", w.wall->brokenLinkCount()}, {"fragments", w.wall->pieceCount()},
                         {"fragments_frozen", w.wall->frozenPieceCount()},
                         {"mass_initial", w.wall->initialMass()}, {"mass_final", w.wall->currentMass()}};
        for (auto [name, field] : std::initializer_list<std::pair<const char*, double FrameTimes::*>>{
                 {"frame", &FrameTimes::total}, {"bullet", &FrameTimes::bullet}, {"lattice", &FrameTimes::lattice},
                 {"impacts", &FrameTimes::impacts}, {"assembly", &FrameTimes::assembly}, {"cg", &FrameTimes::cg},
                 {"breaking", &FrameTimes::breaking}, {"fragments", &FrameTimes::fragments},
                 {"resting", &FrameTimes::resting}})
            out["phases"][name] = phaseStats(frames, field);
        const auto worst = std::max_element(frames.begin(), frames.end(),
                                            [](const FrameTimes& a, const FrameTimes& b) { return a.total < b.total; });
        out["worst_frame"] = frameJson(*worst, int(worst - frames.begin()) + 1);
        if (shatterFrame > 0) out["shatter_frame"] = frameJson(frames[shatterFrame - 1], shatterFrame);
        const CholeskyComparison& c = w.cholesky;
        out["cg_vs_cholesky"] = {{"systems", c.solves},
                                 {"cg_ms_total", 1e3 * c.cgSeconds},
                                 {"cholesky_ms_total", 1e3 * c.choleskySeconds},
                                 {"cholesky_over_cg", c.cgSeconds > 0 ? c.choleskySeconds / c.cgSeconds : 0.0},
                                 {"largest_relative_difference", c.largestDifference}};
        const double medianFrame = out["phases"]["frame"]["median_ms"];
        out["target"] = {{"median_frame_ms", medianFrame}, {"budget_ms", 1000.0 / 60.0}, {"met", medianFrame <= 1000.0 / 60.0}};
        std::printf("shatter-bench-lattice: %d tets, %d links, %d frames: median frame %.2f ms (Bullet %.2f, lattice %.2f), "
                    "worst %.2f ms (frame %d)\n",
                    w.wall->tetCount(), w.wall->linkCount(), o.frames, medianFrame,
                    double(out["phases"]["bullet"]["median_ms"]), double(out["phases"]["lattice"]["median_ms"]),
                    worst->total, int(worst - frames.begin()) + 1);
        if (shatterFrame > 0)
            std::printf("  shatter frame %d: %.2f ms (Bullet %.2f, impacts %.2f, assembly %.2f, CG %.2f, breaking %.2f, "
                        "fragments %.2f), %d links broken, %d CG iterations\n",
                        shatterFrame, frames[shatterFrame - 1].total, frames[shatterFrame - 1].bullet,
                        frames[shatterFrame - 1].impacts, frames[shatterFrame - 1].assembly, frames[shatterFrame - 1].cg,
                        frames[shatterFrame - 1].breaking, frames[shatterFrame - 1].fragments,
                        frames[shatterFrame - 1].linksBroken, frames[shatterFrame - 1].iterations);
        if (o.cholesky)
            std::printf("  CG %.2f ms vs SimplicialLDLT %.2f ms over %d systems: Cholesky/CG = %.2f, largest difference %.2g\n",
                        1e3 * c.cgSeconds, 1e3 * c.choleskySeconds, c.solves,
                        c.cgSeconds > 0 ? c.choleskySeconds / c.cgSeconds : 0.0, c.largestDifference);
        const std::string text = out.dump();
        std::printf("%s\n", text.c_str());
        if (!o.json.empty()) std::ofstream(o.json) << out.dump(2) << "\n";
    } catch (const std::exception& e) {
        std::cerr << "shatter-bench-lattice: error: " << e.what() << "\n";
        return 1;
    }
    return 0;
}
