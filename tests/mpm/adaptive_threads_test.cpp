// The adaptive thread count (AdaptiveThreads.h) never loses much to the better of one and two
// threads, with measured times replaced by a model of the machine (a fake clock), so that the
// tests are deterministic. Times are in seconds, of the size of the drop test's substeps.
#include <shatter/plugin/mpm/AdaptiveThreads.h>

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <utility>

namespace shatter::mpm {
namespace {

constexpr double ms = 1e-3;

// A model machine: the wall time of a substep on `threads` threads that starts at `now`.
using Machine = std::function<double(int threads, double now)>;

struct Tally {
    int substeps = 0;
    int multi = 0;      // substeps on more than one thread
    double seconds = 0; // wall time, adaptive
    double one = 0;     // wall time had every substep run on one thread
};

// Runs `substeps` more substeps on `machine`, from `into.seconds` on, and adds them to `into`.
Tally& run(AdaptiveThreads& control, int substeps, const Machine& machine, Tally& into) {
    for (int k = 0; k < substeps; ++k) {
        const int t = control.threads();
        const double cost = machine(t, into.seconds);
        into.multi += t > 1 ? 1 : 0;
        into.one += machine(1, into.seconds);
        into.seconds += cost;
        ++into.substeps;
        control.record(cost);
    }
    return into;
}

AdaptiveThreads adaptiveTwo() {
    AdaptiveThreads control;
    control.configure(2, true);
    return control;
}

const Machine idle = [](int t, double) { return t == 1 ? 1 * ms : 0.55 * ms; };
const Machine busy = [](int t, double) { return t == 1 ? 1 * ms : 3 * ms; };

// Beside a spinning neighbour, as the scheduler shares two cores among three threads: in every
// 9 ms, 3 ms when both of ours run (a substep on two threads takes 0.55 ms) and 6 ms when one of
// them waits (3 ms a substep). Two threads are 30% slower on average, but a probe that
// starts in a lull sees five fast substeps in a row.
const Machine lulls = [](int t, double now) {
    if (t == 1) return 1 * ms;
    return std::fmod(now, 9 * ms) < 3 * ms ? 0.55 * ms : 3 * ms;
};

TEST(AdaptiveThreads, TwoThreadsAlwaysSlowerCostAtMostTheProbeBudgetAndOneSubstep) {
    // Far slower: a thread that waits for a core a whole scheduler period.
    const Machine awful = [](int t, double) { return t == 1 ? 1 * ms : 10 * ms; };
    // (machine, the longest substep on two threads)
    const std::pair<const Machine*, double> machines[] = {{&busy, 3 * ms}, {&lulls, 3 * ms}, {&awful, 10 * ms}};
    for (const auto& [machine, slowest] : machines)
        // The benchmark's 800 substeps and a long run.
        for (int substeps : {800, 100000}) {
            AdaptiveThreads control = adaptiveTwo();
            Tally tally;
            run(control, substeps, *machine, tally);
            // Each losing probe costs at most one substep's excess, and the probes after the
            // first are spaced so that they cost at most probeBudget of the time between them.
            EXPECT_LE(tally.seconds, (1 + AdaptiveThreads::probeBudget) * tally.one + (slowest - 1 * ms))
                << substeps << " substeps, slowest " << slowest;
            EXPECT_LT(tally.multi, substeps / 50); // a probe that starts in a lull runs on while it keeps up
        }
}

TEST(AdaptiveThreads, TwoThreadsFasterAreTakenAfterOneWindow) {
    AdaptiveThreads control = adaptiveTwo();
    // One untimed substep, one window on one thread, then the probe wins.
    const int onOne = 1 + AdaptiveThreads::window;
    Tally start, longRun;
    run(control, onOne + 40, idle, start);
    EXPECT_EQ(start.multi, 40);
    // Then only the probes of one thread, one substep each, backing off.
    run(control, 100000, idle, longRun);
    EXPECT_GT(longRun.multi, 100000 - 120);
    EXPECT_LT(longRun.seconds, 1.001 * 100000 * 0.55 * ms);
}

TEST(AdaptiveThreads, NeverSlowerThanOneThreadWhileANeighbourComesAndGoes) {
    AdaptiveThreads control = adaptiveTwo();
    Tally total;
    for (int spell = 0; spell < 6; ++spell) {
        run(control, 5000, idle, total);
        // A neighbour comes: within a few windows the count is one thread.
        const int before = total.multi;
        run(control, 4 * AdaptiveThreads::window, busy, total);
        EXPECT_LT(total.multi - before, 3 * AdaptiveThreads::window);
        run(control, 5000, busy, total);
    }
    EXPECT_LT(total.seconds, total.one);
    // It leaves: two threads again within the longest probe interval.
    Tally back, after;
    run(control, (AdaptiveThreads::maxInterval + 2) * AdaptiveThreads::window, idle, back);
    run(control, 4000, idle, after);
    EXPECT_GT(after.multi, 4000 - 20);
}

TEST(AdaptiveThreads, ANeighbourArrivingAtAnyMomentIsNoticedWithinThreeWindows) {
    // Whatever the window or probe schedule is doing when it comes (a scheduled probe right
    // after the first slow window, compared with the window before, loses; the next slow
    // window must still bring a probe).
    constexpr int window = AdaptiveThreads::window;
    for (int moment = 0; moment < (AdaptiveThreads::maxInterval + 2) * window; ++moment) {
        AdaptiveThreads control = adaptiveTwo();
        Tally before, after;
        run(control, 3000 + moment, idle, before);
        run(control, 8 * window, busy, after);
        EXPECT_LT(after.multi, 3 * window) << "neighbour from substep " << 3000 + moment;
    }
}

TEST(AdaptiveThreads, PassingSpikesOnAnIdleMachineDoNotCostProbes) {
    // Nearly idle: every 40th window one substep takes 20 times as long (another process
    // passing by), whatever the thread count.
    AdaptiveThreads control = adaptiveTwo();
    int substep = 0;
    const Machine spiky = [&](int t, double now) {
        const double base = idle(t, now);
        return ++substep % (40 * AdaptiveThreads::window) == 0 ? 20 * base : base;
    };
    Tally settle, settled;
    run(control, 4000, spiky, settle);
    // Only the backed-off probes run on one thread, one substep each (probing a whole window
    // after every spike ran 4 windows in 40 on one thread).
    const int substeps = 40000;
    EXPECT_GT(run(control, substeps, spiky, settled).multi, substeps - 60);
}

TEST(AdaptiveThreads, FixedOrSingleCountsNeverChange) {
    AdaptiveThreads fixed, single;
    fixed.configure(2, false);
    single.configure(1, true);
    Tally a, b;
    EXPECT_EQ(run(fixed, 1000, busy, a).multi, 1000);
    EXPECT_EQ(run(single, 1000, busy, b).multi, 0);
    EXPECT_EQ(fixed.threads(), 2);
    EXPECT_EQ(single.threads(), 1);
}

} // namespace
} // namespace shatter::mpm
