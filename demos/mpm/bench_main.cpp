// shatter-bench-mpm [--quick] [--busy-neighbour] [--phases]: throughput of the 2D crack solver.
//  1. particle-steps per second, with and without a crack, on 1 thread, 2 threads fixed and
//     up to 2 adaptive (AdaptiveThreads.h): the source's drop-test disk (radius 50 m,
//     particle spacing 0.5 m: 31,428 particles), PMMA;
//  2. the source's drop test at 0.5 m spacing, 45 frames of 800 substeps, timed end to end
//     (the source: almost 3 hours; the target: 60 s).
// Timings belong here, not in the tests. --busy-neighbour runs everything twice: as is, then
// beside a process of its own that spins on one core (a game or a DCC tool shares the
// machine), and prints both; a line "=>" per case sums up one thread against up to 2
// adaptive (issue 20: two threads must never be slower than one). OpenMP teams slow down when other processes compete for the
// cores: OpenMpWait.h bounds the spinning, the solver's adaptive thread count the rest.
#include "demos/mpm/OpenMpWait.h"
#include <shatter/plugin/mpm/Solver2D.h>
#include <shatter/plugin/mpm/TransferTargets.h>

#include <CLI/CLI.hpp>

#include <chrono>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <algorithm>
#include <iostream>
#include <string>
#include <vector>
#include <sys/wait.h>
#include <unistd.h>

namespace {

using namespace shatter::mpm;
using Clock = std::chrono::steady_clock;

// `atImpact`: the disk starts touching the ground at the speed of a 5 m fall, so that short
// timed runs see the impact and a loaded crack.
Scene dropScene(bool crack, bool atImpact) {
    Scene s;
    s.source = "drop test";
    s.analysis = Analysis::PlaneStrain;
    s.gravity = Vec2(0, -9.81);
    s.grid.dx = 1.0; // the source: particle separation 0.5 m, cells twice that
    s.grid.ppc = 2;
    s.materials.push_back(*materialPreset("pmma"));
    const double lift = atImpact ? 0.6 : 5;
    const Vec2 velocity(0, atImpact ? -9.9 : 0);
    s.bodies.push_back(Body{Shape(CircleShape{Vec2(0, 50 + lift), 50}), 0, velocity});
    if (crack)
        s.cracks.push_back(CrackSpec{{Vec2(0.25, 40 + lift), Vec2(0.25, 60 + lift)}, true, TipSelection::Both, {}});
    s.colliders.push_back(std::make_shared<HalfPlaneCollider>(Vec2(0, 0), Vec2(0, 1)));
    s.time.frame = 1.0 / 24;
    s.time.end = 45 * s.time.frame;
    s.time.maxStep = s.time.frame / 800; // the source's 800 substeps per frame
    return s;
}

double seconds(Clock::time_point since) { return std::chrono::duration<double>(Clock::now() - since).count(); }

bool printPhases = false; // --phases
bool printHash = false;   // --hash

// FNV-1a over the bits of the particles' state: two builds that should agree to the bit
// (a change that only moves work around) print the same value.
std::uint64_t stateHash(const Solver2D& solver) {
    std::uint64_t h = 1469598103934665603ull;
    const auto add = [&](const auto& values) {
        const auto* bytes = reinterpret_cast<const unsigned char*>(values.data());
        for (size_t k = 0; k < values.size() * sizeof(values[0]); ++k) h = (h ^ bytes[k]) * 1099511628211ull;
    };
    const Particles& P = solver.particles();
    add(P.x);
    add(P.v);
    add(P.C);
    add(P.Fe);
    for (const Crack& c : solver.cracks()) add(c.points);
    return h;
}

// Where the solver's wall time went, per stage (PhaseTimes.h), with --phases.
void phases(const Solver2D& solver) {
    if (!printPhases) return;
    const PhaseTimes& t = solver.phaseTimes();
    double total = 0;
    for (double x : t.seconds) total += x;
    for (size_t k = 0; k < t.seconds.size(); ++k)
        std::printf("    %-22s %8.3f s  %5.1f%%  %7.1f us/substep\n", std::string(PhaseTimes::names[k]).c_str(),
                    t.seconds[k], 100 * t.seconds[k] / total, 1e6 * t.seconds[k] / double(solver.substeps()));
}

// A child process that keeps one core busy until it is killed (the busy neighbour).
class BusyNeighbour {
public:
    BusyNeighbour() {
        pid_ = fork();
        if (pid_ == 0) {
            volatile unsigned long spin = 0;
            for (;;) spin = spin + 1;
        }
        if (pid_ < 0) throw std::runtime_error("could not start the busy neighbour process (fork failed)");
    }
    ~BusyNeighbour() {
        kill(pid_, SIGKILL);
        waitpid(pid_, nullptr, 0);
    }
    BusyNeighbour(const BusyNeighbour&) = delete;
    BusyNeighbour& operator=(const BusyNeighbour&) = delete;

private:
    pid_t pid_ = -1;
};

struct Throughput {
    double rate = 0;          // particle-steps per second
    double multiFraction = 0; // substeps run on more than one thread
    double multiTime = 0;     // their share of the wall time
};

Throughput throughput(bool crack, int threads, bool adaptive, int steps) {
    Solver2D solver(dropScene(crack, true));
    solver.setThreads(threads, adaptive);
    const long before = solver.substeps();
    long multi = 0;
    double multiSeconds = 0;
    const auto start = Clock::now();
    for (int k = 0; k < steps; ++k) {
        const auto substepStart = Clock::now();
        solver.step(1.0);
        if (solver.threadsInUse() > 1) {
            ++multi;
            multiSeconds += seconds(substepStart);
        }
    }
    const double s = seconds(start);
    const long substeps = solver.substeps() - before;
    const Throughput t{double(solver.particles().size()) * double(substeps) / s, double(multi) / double(substeps),
                       multiSeconds / s};
    std::printf("%-14s %-9s %d thread%s  %8zu particles  %6ld substeps  %7.3f s  %6.2f M particle-steps/s",
                crack ? "with crack" : "without crack", threads == 1 ? "" : adaptive ? "up to" : "fixed", threads,
                threads == 1 ? " " : "s", solver.particles().size(), substeps, s, t.rate / 1e6);
    if (threads > 1 && adaptive)
        std::printf("  (%.1f%% of substeps on %d, %.1f%% of the time)", 100 * t.multiFraction, threads,
                    100 * t.multiTime);
    std::printf("\n");
    phases(solver);
    return t;
}

// The throughput rows of one condition (as is, or beside the neighbour); `pairs` times one
// thread and up to 2 adaptive back to back, so that a change in the other load on the
// machine falls on both alike, then the summary the issue asks for: the rates, their ratio
// (median of the pairs) and the share of substeps on two threads.
void throughputRows(const char* condition, int steps, int pairs) {
    for (bool crack : {false, true}) {
        throughput(crack, 2, false, steps);
        std::vector<double> one, adaptive, ratio, multi, multiTime;
        for (int k = 0; k < pairs; ++k) {
            const Throughput a = throughput(crack, 1, false, steps);
            const Throughput b = throughput(crack, 2, true, steps);
            one.push_back(a.rate);
            adaptive.push_back(b.rate);
            ratio.push_back(b.rate / a.rate);
            multi.push_back(b.multiFraction);
            multiTime.push_back(b.multiTime);
        }
        const auto median = [](std::vector<double> v) {
            std::sort(v.begin(), v.end());
            return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
        };
        std::printf("  => %s, %s: 1 thread %.2f, up to 2 adaptive %.2f M particle-steps/s: adaptive/one %.3f "
                    "(median of %d pair%s; range %.3f-%.3f); %.1f%% of substeps on 2 threads, %.1f%% of the time\n",
                    condition, crack ? "with crack" : "without crack", median(one) / 1e6, median(adaptive) / 1e6,
                    median(ratio), pairs, pairs == 1 ? "" : "s", *std::min_element(ratio.begin(), ratio.end()),
                    *std::max_element(ratio.begin(), ratio.end()), 100 * median(multi),
                    100 * median(multiTime));
    }
}

void dropTest(int frames, int threads, bool adaptive) {
    const Scene scene = dropScene(true, false);
    Solver2D solver(scene);
    if (threads > 0 || !adaptive) solver.setThreads(threads > 0 ? threads : solver.threads(), adaptive);
    const auto start = Clock::now();
    for (int f = 0; f < frames; ++f) solver.advance(scene.time.frame);
    const double s = seconds(start);
    std::printf("drop test, 0.5 m spacing: %zu particles, %d frames, %ld substeps (%ld per frame), %s%d threads: "
                "%.1f s (%.2f M particle-steps/s)\n",
                solver.particles().size(), frames, solver.substeps(), solver.substeps() / frames,
                solver.threads() == 1 ? "" : adaptive ? "up to " : "fixed ", solver.threads(), s,
                double(solver.particles().size()) * double(solver.substeps()) / s / 1e6);
    phases(solver);
    for (const TipResult& t : solver.tips())
        std::printf("  tip %s at (%.2f, %.2f): K_I %.3g Pa√m, grew %d times in the last frame\n",
                    t.tip == 0 ? "start" : "end", t.position.x(), t.position.y(), t.KI, t.grew);
}

} // namespace

int main(int argc, char** argv) {
    shatter::mpm::demo::boundOpenMpSpinning(argv);
    CLI::App app("Throughput of the 2D MPM crack solver", "shatter-bench-mpm");
    bool quick = false;
    int threads = 0;
    int substeps = -1;
    bool crack = false;
    bool dropOnly = false;
    bool busy = false;
    int dropFrames = 45;
    bool fixedThreads = false;
    int pairs = 1;
    app.add_flag("--quick", quick, "Fewer steps and 3 drop-test frames: a smoke run");
    app.add_option("--substeps", substeps,
                   "Only step the throughput scene this many substeps on --threads (default 1) threads and "
                   "print nothing: for instruction counts (callgrind) of N substeps minus 0 substeps")
        ->check(CLI::NonNegativeNumber);
    app.add_flag("--crack", crack, "With --substeps: the scene with the crack");
    app.add_flag("--drop-only", dropOnly, "Only the timed drop test, not the throughput table");
    app.add_option("--threads", threads, "Threads for the drop test (default: all cores)")->check(CLI::PositiveNumber);
    app.add_option("--drop-frames", dropFrames, "Frames of the drop test (default 45, the source's; 0: none)")
        ->check(CLI::NonNegativeNumber);
    app.add_flag("--fixed-threads", fixedThreads,
                 "The drop test (and --substeps) on exactly --threads threads (default: adaptive, at most)");
    app.add_flag("--busy-neighbour", busy,
                 "Run everything twice: as is, then beside a process of its own spinning on one core");
    app.add_option("--pairs", pairs,
                   "Throughput: time one thread and up to 2 adaptive this many times back to back (default 1); "
                   "the summary gives the median ratio")
        ->check(CLI::PositiveNumber);
    app.add_flag("--hash", printHash, "With --substeps: print a hash of the particles' and cracks' state (bit-identity checks)");
    app.add_flag("--phases", printPhases, "After each timed run, the wall time of each stage of the substeps");
    app.add_flag("--generic", forceGenericTransfers(),
                 "Run the generic copy of the transfers even on an x86-64-v3 (AVX2) CPU, to time it");
    app.add_flag("--no-avx512", forceX86_64_v3Transfers(),
                 "Run the x86-64-v3 (AVX2) copies of the transfers even on an x86-64-v4 (AVX-512) CPU, to time them");
    app.failure_message([](const CLI::App* a, const CLI::Error& e) {
        return "shatter-bench-mpm: error: " + CLI::FailureMessage::simple(a, e);
    });
    CLI11_PARSE(app, argc, argv);
    std::setvbuf(stdout, nullptr, _IOLBF, 0); // rows appear as they are measured, also in a log
    try {
        if (substeps >= 0) {
            Solver2D solver(dropScene(crack, true));
            solver.setThreads(threads > 0 ? threads : 1, !fixedThreads);
            long oneThread = 0;
            for (int k = 0; k < substeps; ++k) {
                solver.step(1.0);
                oneThread += solver.threadsInUse() == 1;
            }
            if (printPhases) std::printf("    substeps on one thread: %ld of %d\n", oneThread, substeps);
            phases(solver);
            if (printHash) std::printf("%016llx\n", static_cast<unsigned long long>(stateHash(solver)));
            return 0;
        }
        const int steps = quick ? 50 : 800;
        auto run = [&](const char* condition) {
            if (!dropOnly) throughputRows(condition, steps, pairs);
            if (dropFrames > 0) dropTest(quick ? std::min(3, dropFrames) : dropFrames, threads, !fixedThreads);
        };
        if (busy) std::printf("-- machine as it is\n");
        run("as is");
        if (busy) {
            const BusyNeighbour neighbour;
            std::printf("-- beside a busy neighbour process (one core spinning)\n");
            run("beside a busy neighbour");
        }
        return 0;
    } catch (const std::exception& e) {
        std::cerr << "shatter-bench-mpm: error: " << e.what() << std::endl;
        return 1;
    }
}
