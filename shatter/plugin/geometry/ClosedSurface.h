#pragma once
// Whether polygon faces form closed surfaces, with vertices at identical coordinates counted
// as one (meshes exported with split vertices are still closed).
#include <Eigen/Core>
#include <vector>

namespace shatter::geometry {

// For every point, the smallest index of a point with identical coordinates.
std::vector<int> coincidentRepresentatives(const std::vector<Eigen::Vector3d>& points);

// True when there are at least four faces and every edge is used exactly once in each
// direction (faces given over the representatives above, so coincident vertices are one).
bool isClosedSurface(const std::vector<std::vector<int>>& faces);

} // namespace shatter::geometry
