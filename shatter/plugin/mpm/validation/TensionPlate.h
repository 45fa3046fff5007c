#pragma once
// The quasi-static test plate the crack validation cases share: a linear-elastic plate in
// plane stress on one-metre cells, pulled by a remote tension σ on its top and bottom edges
// (ramped over one wave transit), with near-critical grid damping so it settles.
#include <shatter/plugin/mpm/Scene.h>

#include <string>

namespace shatter::mpm::validation {

constexpr double kPlateDx = 1.0; // the cases are scale-free: one-metre cells

// Plane-stress P-wave speed of the plate's material (m/s).
double plateWaveSpeed();
// Time for a wave to cross `height` (s).
inline double plateTransit(double height) { return height / plateWaveSpeed(); }

// The plate [0, width] × [0, height] with its material, loads and damping, and time.end set
// to `maxTransits` transits of the height. The caller adds the crack.
Scene tensionPlate(const std::string& source, double width, double height, double sigma, int ppc, KernelType kernel,
                   int maxTransits);

} // namespace shatter::mpm::validation
