#pragma once
// Voronoi cells of point sites inside a box, computed by voro++ (the only file that
// includes it). Shared by the Voronoi and grid patterns.
#include <shatter/plugin/fracture/FracturePattern.h>
#include <shatter/plugin/geometry/Aabb.h>

namespace shatter::fracture {

// The pattern of the sites' cells clipped to `box` (in site order; centres = sites), with
// `radius` as given; a site outside the box is an error. Calls finishPattern.
FracturePattern voronoiCellsPattern(const std::vector<Eigen::Vector3d>& sites, const geometry::Aabb& box,
                                    double radius);

} // namespace shatter::fracture
