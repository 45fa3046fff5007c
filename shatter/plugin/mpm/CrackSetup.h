#pragma once
// Builds the run-time cracks from the scene: each polyline is resampled so that no segment
// is longer than one growth step (the crack-opening fit behind a tip needs several crack
// particles within the J contour), tips are switched on as the scene says, and a guide path
// is resampled at the growth length and given to the tip nearest to its first point.
#include <shatter/plugin/mpm/Crack.h>
#include <shatter/plugin/mpm/Scene.h>

#include <vector>

namespace shatter::mpm {

std::vector<Crack> buildCracks(const Scene& scene);

// Points along `path` every `step` metres, starting one step after path[0], ending at its
// last point.
std::vector<Vec2> resamplePath(const std::vector<Vec2>& path, double step);

} // namespace shatter::mpm
