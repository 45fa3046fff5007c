#pragma once
// Seconds since a steady-clock time point: the one clock behind every phase timing the modules'
// systems and results report (FractureResult::seconds, the systems' Timing structs).
#include <chrono>

namespace shatter {

using SteadyClock = std::chrono::steady_clock;

inline double secondsSince(SteadyClock::time_point t) {
    return std::chrono::duration<double>(SteadyClock::now() - t).count();
}

} // namespace shatter
