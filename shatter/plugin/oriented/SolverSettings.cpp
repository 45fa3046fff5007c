#include <shatter/plugin/oriented/SolverSettings.h>

#include <shatter/plugin/common/SettingCheck.h>

#include <algorithm>
#include <cmath>

namespace shatter::oriented {

double stableChebyshevRadius(int iterations) {
    if (iterations < 2) return 0.0;
    return 1.0 / std::cosh(std::acosh(4.0) / iterations);
}

double maxChebyshevRadius(int iterations) {
    return iterations < 2 ? kMaxChebyshevRadius : std::min(kMaxChebyshevRadius, stableChebyshevRadius(iterations));
}

void SolverSettings::check(const std::string& body) const {
    requireWithin(body, "stiffness", stiffness, 0.0, 1.0);
    requireAtLeast(body, "iterations", iterations, 1);
    requireWithin(body, "Chebyshev radius at " + std::to_string(iterations) + " sweeps", chebyshevRadius, 0.0,
                  maxChebyshevRadius(iterations));
    requireAtLeast(body, "rotation iterations", rotationIterations, 1);
    requireAtLeast(body, "substeps per step", substepsPerStep, 1);
    requireNonNegative(body, "damping (1/s)", damping);
    requireNonNegative(body, "epsilon (rad)", epsilon);
    requireNonNegative(body, "sleep speed (m/s)", sleepSpeed);
    requireNonNegative(body, "sleep time (s)", sleepTime);
    requireSetting(gravity.allFinite(), body, "gravity (m/s²)", "finite", gravity.norm());
    requireSetting(simdPathAvailable(simdPath), body, "SIMD path (0 portable, 1 AVX2)", "one this processor runs",
                   double(int(simdPath)));
}

} // namespace shatter::oriented
