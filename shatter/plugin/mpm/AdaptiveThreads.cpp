#include <shatter/plugin/mpm/AdaptiveThreads.h>

#include <algorithm>

namespace shatter::mpm {

void AdaptiveThreads::configure(int maximum, bool adaptive) {
    *this = AdaptiveThreads{};
    maximum_ = std::max(1, maximum);
    adaptive_ = adaptive && maximum_ > 1;
    current_ = maximum_;
}

void AdaptiveThreads::startWindow() {
    taken_ = 0;
    sum_ = 0;
}

void AdaptiveThreads::record(double seconds) {
    if (!adaptive_) return;
    sum_ += seconds;
    if (++taken_ < window) return;
    const double mean = sum_ / taken_;
    startWindow();
    if (probing_) {
        probing_ = false;
        if (mean < 0.9 * reference_) { // the other count is clearly faster: take it
            current_ = other();
            reference_ = mean;
            interval_ = baseInterval;
        } else {
            interval_ = std::min(2 * interval_, maxInterval);
        }
        untilProbe_ = interval_;
        return;
    }
    // Several threads and much slower for two windows in a row: another process has probably
    // started; look again at once. One slow window alone (a short process passing by) is not
    // enough: probing after each one, and restarting the backoff, ran 9-12% of the substeps of
    // 2,400 at impact on one thread, with nothing else running but the kernel's pauses of
    // real-time tasks (shatter-bench-mpm --substeps 2400 --crack --threads 2 --phases under
    // chrt -f). The slow window is compared with the normal one before it, so it does not
    // become the reference.
    // (On one thread the backed-off probes find out when a neighbour leaves: one thread is
    // never far from the best.)
    if (current_ > 1 && reference_ > 0 && mean > 1.5 * reference_) {
        if (++slowWindows_ < 2) {
            if (--untilProbe_ <= 0) probing_ = true;
            return;
        }
        untilProbe_ = 1;
    }
    slowWindows_ = 0;
    reference_ = mean;
    if (--untilProbe_ <= 0) probing_ = true;
}

} // namespace shatter::mpm
