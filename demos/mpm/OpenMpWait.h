#pragma once
// OpenMP threads that reach a barrier first spin, by default for up to ~300,000 iterations
// (libgomp), before they sleep. A substep of the MPM solver has several barriers, and on a
// machine whose cores are busy with other processes a spinning thread keeps a core while the
// thread it waits for is descheduled: two threads then ran 3-15 times slower than one.
// libgomp reads its settings once, when it is loaded, so the program sets a short spin
// (GOMP_SPINCOUNT=10000: a few microseconds, enough for the barriers of a balanced substep,
// then sleep) and starts itself again. A user's own OMP_WAIT_POLICY or GOMP_SPINCOUNT wins.
#include <cstdlib>
#include <unistd.h>

namespace shatter::mpm::demo {

inline void boundOpenMpSpinning(char** argv) {
    if (std::getenv("OMP_WAIT_POLICY") || std::getenv("GOMP_SPINCOUNT")) return;
    setenv("GOMP_SPINCOUNT", "10000", 1);
    execv("/proc/self/exe", argv); // returns only on failure: then run with the defaults
}

} // namespace shatter::mpm::demo
