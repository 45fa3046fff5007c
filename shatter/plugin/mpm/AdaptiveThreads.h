#pragma once
// How many threads the next substeps use, chosen from the measured wall time per substep
// (issue 20). On a machine where another process holds a core, a team of two OpenMP threads
// waits at every barrier of a substep for whichever thread the scheduler has set aside: two
// threads ran the drop test three times slower than one (3.8 M against 12 M particle-steps
// per second). Whether that happens depends on the rest of the machine, which changes while
// a simulation runs, so the solver measures instead of guessing: it runs windows of
// `window` substeps with the current count and, now and then, one window with the other
// candidate (1 or the maximum), and keeps the faster. A probe that loses doubles the
// interval to the next one (up to `maxInterval` windows), so a settled choice costs about
// one slow window in 129; on several threads, two windows in a row 1.5 times slower than the
// one before them (another process started) bring the next probe forward. Results do not depend on the thread count, so
// switching changes timings only.
#include <cstdint>

namespace shatter::mpm {

class AdaptiveThreads {
public:
    // A losing probe costs one window at the slow count: short windows keep that small (8
    // substeps of the drop test are 30-80 ms, many scheduler slices).
    static constexpr int window = 8;        // substeps per measurement
    static constexpr int baseInterval = 8;  // windows between probes after a change
    static constexpr int maxInterval = 128;

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
    void startWindow();

    int maximum_ = 1;
    bool adaptive_ = false;
    int current_ = 1;
    bool probing_ = false;
    int taken_ = 0;                 // substeps in this window
    double sum_ = 0;                // their wall time
    double reference_ = 0;          // mean substep time of the last window at current_ (0: none yet)
    int interval_ = baseInterval;   // windows between probes
    int untilProbe_ = 1;            // windows left before the next probe
    int slowWindows_ = 0;           // consecutive windows 1.5 times slower than reference_
};

} // namespace shatter::mpm
