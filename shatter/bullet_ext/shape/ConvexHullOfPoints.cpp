#include <shatter/bullet_ext/shape/ConvexHullOfPoints.h>

#include <shatter/bullet_ext/Convert.h>
#include <shatter/plugin/common/InputError.h>

#include <LinearMath/btConvexHullComputer.h>

#include <string>

namespace shatter {

geometry::ConvexPolyhedron convexHullOf(const std::vector<Eigen::Vector3d>& points) {
    btConvexHullComputer hull;
    if (points.size() >= 4)
        hull.compute(points.front().data(), int(sizeof(Eigen::Vector3d)), int(points.size()), 0.0, 0.0);
    if (hull.faces.size() < 4)
        throw InputError("convexHullOf: " + std::to_string(points.size()) + " points span no volume");
    // The computer's own vertices (its grid points, as Bullet's hull keeps them), not the input
    // points they came from: its faces are planar and convex on its grid, and a sliver face
    // through the input points may be neither (a vase shard had vertices 3.5 cm outside such a
    // face's plane).
    std::vector<Eigen::Vector3d> vertices(size_t(hull.vertices.size()));
    std::vector<int> ids(vertices.size());
    for (size_t i = 0; i < vertices.size(); ++i) {
        ids[i] = hull.original_vertex_index[int(i)];
        vertices[i] = toEigen(hull.vertices[int(i)]);
    }
    std::vector<std::vector<int>> faces(static_cast<size_t>(hull.faces.size()));
    for (size_t f = 0; f < faces.size(); ++f) {
        const btConvexHullComputer::Edge* start = &hull.edges[hull.faces[int(f)]];
        const btConvexHullComputer::Edge* e = start;
        do { // counter-clockwise around the face, seen from outside
            faces[f].push_back(e->getSourceVertex());
            e = e->getNextEdgeOfFace();
        } while (e != start);
    }
    return geometry::ConvexPolyhedron::createTrusted(std::move(vertices), std::move(faces), std::move(ids));
}

} // namespace shatter
