#pragma once
// Extrusion of an open-surface face into convex prisms (source 000 §3.1): the face is
// pushed along its negative normal by the thickness.
#include <shatter/plugin/geometry/ConvexPolyhedron.h>

#include <Eigen/Core>
#include <string>
#include <vector>

namespace shatter::geometry {

// Right prism under a convex polygon (collinear vertices allowed). Its top is the polygon
// itself, vertex i carrying global id polygon[i]; its bottom is the polygon moved by
// -thickness·unitNormal, carrying id visualVertexCount + polygon[i], so that bottoms of
// neighbouring prisms share ids and weld into an inner surface. Throws InputError
// (naming `what`) when the result is not a valid convex solid.
ConvexPolyhedron extrudeConvexPolygon(const std::vector<Eigen::Vector3d>& points, const std::vector<int>& polygon,
                                      const Eigen::Vector3d& unitNormal, double thickness, int visualVertexCount,
                                      const std::string& what);

// Prisms for one face: a single prism along the Newell normal when the face is convex and
// planar within planarityTolerance (metres); otherwise one prism per ear-clipping
// triangle, each along its own normal (so each is a right prism of volume area·thickness).
std::vector<ConvexPolyhedron> extrudeFace(const std::vector<Eigen::Vector3d>& points, const std::vector<int>& face,
                                          double thickness, double planarityTolerance, int visualVertexCount,
                                          const std::string& what);

// How many prisms extrudeFace makes of the face, without making them: 1 or its
// face.size() - 2 triangles (an underestimate only where a flat convex face's prism fails
// its own flatness check and extrudeFace splits it after all).
int prismCount(const std::vector<Eigen::Vector3d>& points, const std::vector<int>& face, double planarityTolerance);

} // namespace shatter::geometry
