#include <shatter/plugin/mpm/TimeStep.h>

#include <algorithm>
#include <stdexcept>
#include <string>

namespace shatter::mpm {

double stableTimeStep(const SimulationState& s) {
    if (!std::isfinite(s.fastestSignal))
        throw std::runtime_error("a particle's velocity or deformation became non-finite at t = " +
                                 std::to_string(s.time) + " s");
    if (s.fastestSignal <= 0) return s.scene.time.maxStep;
    return std::min(s.scene.time.cfl * s.scene.grid.dx / s.fastestSignal, s.scene.time.maxStep);
}

} // namespace shatter::mpm
