#pragma once
// Closed convex parts of a visual mesh (source 000 §3.1): connected groups of faces that
// enclose a convex volume become one primitive each, without extrusion.
#include <shatter/plugin/geometry/ConvexPolyhedron.h>

#include <Eigen/Core>
#include <vector>

namespace shatter::geometry {

struct ClosedConvexPart {
    std::vector<int> faces; // indices into the face list, ascending
    bool flipped = false;   // the faces were wound inward; the primitive has them reversed
    ConvexPolyhedron primitive;
};

// Groups faces into parts connected through shared vertices (vertices at identical
// coordinates count as one) and returns, in order of their first face, the parts that
// are closed (every edge used by exactly two faces, in opposite directions) and convex
// (every vertex at most convexityTolerance in front of every face plane). A part wound
// inward is flipped. The primitive's vertices carry their point index as global id;
// a vertex at the same coordinates as another one of the part is kept as an extra
// vertex (on no face) so that it still carries its id.
std::vector<ClosedConvexPart> findClosedConvexParts(const std::vector<Eigen::Vector3d>& points,
                                                    const std::vector<std::vector<int>>& faces,
                                                    double convexityTolerance);

} // namespace shatter::geometry
