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
    // Several threads and suddenly much slower: another process has probably started; look
    // again soon. (On one thread the backed-off probes find out when it leaves: one thread
    // is never far from the best, and on a loaded machine window times swing by 1.5 often
    // enough that probing on every swing cost 30% in the benchmark.)
    if (current_ > 1 && reference_ > 0 && mean > 1.5 * reference_) {
        interval_ = baseInterval;
        untilProbe_ = std::min(untilProbe_, 1);
    }
    reference_ = mean;
    if (--untilProbe_ <= 0) probing_ = true;
}

} // namespace shatter::mpm
