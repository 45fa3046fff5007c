#include <shatter/plugin/mpm/AdaptiveThreads.h>

#include <algorithm>
#include <cmath>

namespace shatter::mpm {

void AdaptiveThreads::configure(int maximum, bool adaptive) {
    *this = AdaptiveThreads{};
    maximum_ = std::max(1, maximum);
    adaptive_ = adaptive && maximum_ > 1;
    current_ = adaptive_ ? 1 : maximum_; // adaptive: one window on one thread, then a probe
}

void AdaptiveThreads::record(double seconds) {
    if (!adaptive_) return;
    if (probing_) {
        recordProbe(seconds);
        return;
    }
    // The first substep of a run, or after a change of count, also pays for first touches of
    // memory or the other thread waking up: not a measure of the count.
    if (taken_ < 0) {
        taken_ = 0;
        return;
    }
    sum_ += seconds;
    if (++taken_ < window) return;
    const double mean = sum_ / taken_;
    const double ref = fasterOfLastTwo();
    taken_ = 0;
    sum_ = 0;
    // Several threads and much slower for two windows in a row: another process has probably
    // started; look at once. One slow window alone (a short process passing by) is not
    // enough: probing after each one ran 9-12% of the substeps of 2,400 at impact on one
    // thread with nothing else running but the kernel's pauses of real-time tasks, when
    // probes were whole windows (shatter-bench-mpm --substeps 2400 --crack --threads 2 --phases
    // under chrt -f). That probe is compared with the last window, the slow one: the one
    // before may have been slowed only in part, and the machine is now as the last one saw it.
    bool slow = false;
    if (current_ > 1 && ref > 0 && mean > 1.5 * ref) {
        slow = ++slowWindows_ >= 2;
        if (slow) untilProbe_ = 1;
    } else {
        slowWindows_ = 0;
    }
    before_ = last_;
    last_ = mean;
    if (--untilProbe_ <= 0) {
        probing_ = true;
        probeReference_ = slow ? mean : fasterOfLastTwo();
        probeTaken_ = 0;
        probeSum_ = 0;
    }
}

void AdaptiveThreads::recordProbe(double seconds) {
    probeSum_ += seconds;
    ++probeTaken_;
    const double ref = probeReference_;
    // Slower so far: stop now, so a losing probe costs at most this one substep's excess.
    if (probeSum_ > probeTaken_ * ref) {
        endProbe(false);
        return;
    }
    if (probeTaken_ >= probeLength && probeSum_ >= probeSeconds)
        endProbe(probeSum_ < (1 - margin) * probeTaken_ * ref);
}

void AdaptiveThreads::endProbe(bool won) {
    probing_ = false;
    taken_ = -1; // the count changes back or for good: the next substep is not timed
    sum_ = 0;
    if (won) {
        current_ = other();
        slowWindows_ = 0;
        last_ = probeSum_ / probeTaken_;
        before_ = 0;
        interval_ = firstInterval;
        untilProbe_ = 2; // probe the old count again soon: cheap if this change was right
    } else {
        // (slowWindows_ is kept: a scheduled probe compared with a window from before a
        // neighbour came loses, and the next slow window must still bring the next one forward.)
        // The windows at the current count of which this probe's loss is probeBudget.
        const double excess = probeSum_ - probeTaken_ * probeReference_;
        const double budget = excess > 0 ? std::ceil(excess / (probeBudget * window * probeReference_)) : 0;
        untilProbe_ = std::max(interval_, int(std::min(budget, double(budgetCap))));
        interval_ = std::min(2 * interval_, maxInterval);
    }
}

} // namespace shatter::mpm
