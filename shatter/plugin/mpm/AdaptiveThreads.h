#pragma once
// How many threads the next substeps use, chosen from the measured wall time per substep
// (issue 20). On a machine where another process holds a core, a team of two OpenMP threads
// waits at every barrier of a substep for whichever thread the scheduler has set aside: two
// threads ran the drop test three times slower than one (3.8 M against 12 M particle-steps
// per second). Whether that happens depends on the rest of the machine, which changes while
// a simulation runs, so the solver measures instead of guessing.
//
// The rule, and why it never costs more than about 1% against the better count:
// - The current count runs in windows of `window` substeps. A probe's reference is the faster
//   of the last two windows, measured just before it (the same conditions); the faster, so
//   that one window slowed by a process passing by does not lower the bar.
// - Now and then a probe runs the other count (1 or the maximum) one substep at a time and
//   stops as soon as its running mean is slower than the reference. So a losing probe costs
//   at most one substep's excess over the reference, however long probes may run.
// - A probe that keeps up for `probeLength` substeps and `probeSeconds` (several scheduler
//   slices, so that a short lull of the neighbour does not decide) and is `margin` faster
//   wins: the count changes. Being long costs nothing: it is faster all along.
// - After a losing probe the next one waits until the loss is at most `probeBudget` of the
//   time run in between (at most `budgetCap` windows), and at least `interval` windows,
//   which doubles with each loss from `firstInterval` to `maxInterval`. So losing probes
//   cost at most probeBudget of the run after the first probe, and on an idle machine one
//   substep in maxInterval * window + 1.
// - The solver starts on one thread for one window (its reference) and then probes the
//   maximum: starting on two would cost a whole window at the slow count when a neighbour is
//   busy, and one thread's first window costs about half a window when the machine is idle.
// - After a change the old count is probed again two windows later (cheap if the change was
//   right, a quick way back if it was not).
// - On several threads, two windows in a row 1.5 times slower than the reference (another
//   process started) bring the next probe forward; one slow window (a process passing by)
//   does not. That probe's reference is the last window, the slow one. On one thread nothing
//   is brought forward: a neighbour on the other core does not slow one thread, and the
//   backed-off probes find out when it leaves.
// Results do not depend on the thread count, so switching changes timings only.
#include <algorithm>

namespace shatter::mpm {

class AdaptiveThreads {
public:
    static constexpr int window = 8;               // substeps per measurement at the current count
    static constexpr int probeLength = 16;         // substeps a winning probe needs at least
    static constexpr double probeSeconds = 0.02;   // and wall time (a few scheduler slices)
    static constexpr double margin = 0.1;          // a winning probe is this much faster
    static constexpr double probeBudget = 0.005;   // share of the time losing probes may cost
    static constexpr int firstInterval = 16;       // windows to the next probe after a change
    static constexpr int maxInterval = 128;        // the doubling interval stops here
    static constexpr int budgetCap = 512;          // windows between probes at most

    // `maximum` threads at most; `adaptive` false: always `maximum`.
    void configure(int maximum, bool adaptive);
    // The thread count for the next substep.
    int threads() const { return probing_ ? other() : current_; }
    // The wall time of the substep just taken with threads().
    void record(double seconds);
    int maximum() const { return maximum_; }
    bool adaptive() const { return adaptive_; }

private:
    int other() const { return current_ == 1 ? maximum_ : 1; }
    double fasterOfLastTwo() const { return before_ > 0 ? std::min(last_, before_) : last_; }
    void recordProbe(double seconds);
    void endProbe(bool won);

    int maximum_ = 1;
    bool adaptive_ = false;
    int current_ = 1;
    bool probing_ = false;
    int taken_ = -1;                // substeps in this window (-1: the first substep, not timed)
    double sum_ = 0;                // their wall time
    double last_ = 0;               // mean substep time of the last window at current_ (0: none)
    double before_ = 0;             // and of the one before it
    double probeReference_ = 0;     // mean substep time the running probe has to beat
    int probeTaken_ = 0;            // substeps of the running probe
    double probeSum_ = 0;           // their wall time
    int interval_ = firstInterval;  // windows from a losing probe to the next
    int untilProbe_ = 1;            // windows left before the next probe
    int slowWindows_ = 0;           // consecutive windows 1.5 times slower than the reference
};

} // namespace shatter::mpm
