#pragma once
// Triangles of one mesh polygon, for the outputs that only draw triangles (the depth-buffered
// renderer, glTF). Faces of a VisualMesh may be non-convex (an L-shaped OBJ face) and, once
// a body deforms, slightly non-planar.
#include <Eigen/Core>

#include <array>
#include <vector>

namespace shatter::demo {

// Ear clipping in the polygon's best-fit plane (Newell's normal), so a non-convex polygon
// gives triangles inside it, counter-clockwise like the polygon; indices are into `polygon`.
// A polygon with fewer than 3 corners gives none; one ear clipping cannot resolve (self-
// intersecting, or degenerate to a line) falls back to a fan, which still covers it.
std::vector<std::array<int, 3>> polygonTriangles(const std::vector<Eigen::Vector3d>& polygon);

} // namespace shatter::demo
