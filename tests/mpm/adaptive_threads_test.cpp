// The adaptive thread count (AdaptiveThreads.h) settles on whichever count is faster, with
// measured times replaced by a model of the machine, so that the test is deterministic.
#include <shatter/plugin/mpm/AdaptiveThreads.h>

#include <gtest/gtest.h>

#include <functional>

namespace shatter::mpm {
namespace {

// Runs `substeps` substeps whose wall time is cost(threads); returns the substeps run on
// more than one thread.
int run(AdaptiveThreads& control, int substeps, const std::function<double(int)>& cost) {
    int multi = 0;
    for (int k = 0; k < substeps; ++k) {
        const int t = control.threads();
        multi += t > 1 ? 1 : 0;
        control.record(cost(t));
    }
    return multi;
}

TEST(AdaptiveThreads, ABusyMachineFallsBackToOneThreadAndProbesRarely) {
    // The busy machine: two threads three times slower than one.
    AdaptiveThreads control;
    control.configure(2, true);
    const auto busy = [](int t) { return t == 1 ? 1.0 : 3.0; };
    run(control, 4 * AdaptiveThreads::window, busy);
    EXPECT_EQ(control.threads(), 1);
    // Settled: the probes with two threads back off to one window in maxInterval + 1.
    run(control, 20000, busy);
    const int multi = run(control, 40000, busy);
    EXPECT_LT(multi, 40000 / AdaptiveThreads::maxInterval + AdaptiveThreads::window);
}

TEST(AdaptiveThreads, AnIdleMachineKeepsBothThreadsAndComesBackAfterABusySpell) {
    AdaptiveThreads control;
    control.configure(2, true);
    const auto idle = [](int t) { return t == 1 ? 1.0 : 0.55; };
    const auto busy = [](int t) { return t == 1 ? 1.0 : 3.0; };
    // (Counts of substeps, not threads() at one instant, which may fall in a probe.)
    run(control, 2000, idle);
    EXPECT_GT(run(control, 20000, idle), 20000 * 9 / 10);
    // A neighbour starts: the next windows are 1.5 times slower or more, so a probe follows at once.
    EXPECT_LT(run(control, 4 * AdaptiveThreads::window, busy), 3 * AdaptiveThreads::window);
    EXPECT_LT(run(control, 4000, busy), 4000 / 8);
    // The neighbour leaves: two threads are back within a few probe intervals.
    run(control, 2 * (AdaptiveThreads::maxInterval + 1) * AdaptiveThreads::window, idle);
    EXPECT_GT(run(control, 4000, idle), 4000 * 9 / 10);
}

TEST(AdaptiveThreads, PassingSpikesOnAnIdleMachineDoNotCostProbes) {
    // Nearly idle: every 40th window one substep takes 20 times as long (another process
    // passing by), whatever the thread count.
    AdaptiveThreads control;
    control.configure(2, true);
    int substep = 0;
    const auto spiky = [&](int t) {
        const double base = t == 1 ? 1.0 : 0.55;
        return ++substep % (40 * AdaptiveThreads::window) == 0 ? 20 * base : base;
    };
    run(control, 4000, spiky);
    // Only the backed-off probes run on one thread: about one window in maxInterval + 1
    // (probing after every spike ran 4 windows in 40 on one thread).
    const int substeps = 40000;
    EXPECT_GT(run(control, substeps, spiky), substeps - 2 * substeps / AdaptiveThreads::maxInterval);
}

TEST(AdaptiveThreads, FixedOrSingleCountsNeverChange) {
    AdaptiveThreads fixed, single;
    fixed.configure(2, false);
    single.configure(1, true);
    const auto busy = [](int t) { return t == 1 ? 1.0 : 3.0; };
    EXPECT_EQ(run(fixed, 1000, busy), 1000);
    EXPECT_EQ(run(single, 1000, busy), 0);
    EXPECT_EQ(fixed.threads(), 2);
    EXPECT_EQ(single.threads(), 1);
}

} // namespace
} // namespace shatter::mpm
