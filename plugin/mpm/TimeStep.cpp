#include "plugin/mpm/TimeStep.h"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace shatter::mpm {

double fastestSignal(const SimulationState& s) {
    const Particles& P = s.particles;
    const long n = long(P.size());
    double fastest = 0;
#pragma omp parallel for schedule(static) reduction(max : fastest) num_threads(s.threads)
    for (long p = 0; p < n; ++p) {
        const size_t k = size_t(p);
        fastest = std::max(fastest, finiteOrInfinite(signalSpeed(s.models[P.material[k]], P.Fe[k], P.Fp[k], P.v[k])));
    }
    return fastest;
}

double stableTimeStep(const SimulationState& s) {
    if (!std::isfinite(s.fastestSignal))
        throw std::runtime_error("a particle's velocity or deformation became non-finite at t = " +
                                 std::to_string(s.time) + " s");
    if (s.fastestSignal <= 0) return s.scene.time.maxStep;
    return std::min(s.scene.time.cfl * s.scene.grid.dx / s.fastestSignal, s.scene.time.maxStep);
}

} // namespace shatter::mpm
