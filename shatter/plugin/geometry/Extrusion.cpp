#include <shatter/plugin/geometry/Extrusion.h>

#include <shatter/plugin/geometry/Polygon.h>

namespace shatter::geometry {

ConvexPolyhedron extrudeConvexPolygon(const std::vector<Eigen::Vector3d>& points, const std::vector<int>& polygon,
                                      const Eigen::Vector3d& unitNormal, double thickness, int visualVertexCount,
                                      const std::string& what) {
    const int k = int(polygon.size());
    const Eigen::Vector3d offset = -thickness * unitNormal;
    std::vector<Eigen::Vector3d> vertices;
    std::vector<int> ids;
    vertices.reserve(2 * k);
    ids.reserve(2 * k);
    for (int i : polygon) {
        vertices.push_back(points[i]);
        ids.push_back(i);
    }
    for (int i : polygon) {
        vertices.push_back(points[i] + offset);
        ids.push_back(visualVertexCount + i);
    }
    std::vector<std::vector<int>> faces;
    faces.reserve(k + 2);
    std::vector<int> top(k), bottom(k);
    for (int i = 0; i < k; ++i) {
        top[i] = i;
        bottom[i] = 2 * k - 1 - i; // reversed: seen from below it is counter-clockwise
    }
    faces.push_back(std::move(top));
    faces.push_back(std::move(bottom));
    // Side of edge i→j: outward normal (p_j − p_i) × n, i.e. the quad i, i', j', j.
    for (int i = 0; i < k; ++i) {
        const int j = (i + 1) % k;
        faces.push_back({i, k + i, k + j, j});
    }
    return ConvexPolyhedron::create(std::move(vertices), std::move(faces), std::move(ids), what);
}

namespace {

std::vector<ConvexPolyhedron> extrudeTriangles(const std::vector<Eigen::Vector3d>& points, const std::vector<int>& face,
                                               const Eigen::Vector3d& unitNormal, double thickness,
                                               int visualVertexCount, const std::string& what) {
    std::vector<ConvexPolyhedron> prisms;
    for (const auto& t : triangulatePolygon(points, face, unitNormal)) {
        const std::vector<int> triangle(t.begin(), t.end());
        const Eigen::Vector3d n = polygonAreaVector(points, triangle).normalized();
        prisms.push_back(extrudeConvexPolygon(points, triangle, n, thickness, visualVertexCount, what));
    }
    return prisms;
}

// One prism for the whole face: a triangle, or a convex polygon flat within the tolerance.
bool extrudesWhole(const std::vector<Eigen::Vector3d>& points, const std::vector<int>& face,
                   const Eigen::Vector3d& unitNormal, double planarityTolerance) {
    return face.size() == 3 || (planarityError(points, face, unitNormal) <= planarityTolerance &&
                                isConvexPolygon(points, face, unitNormal));
}

} // namespace

int prismCount(const std::vector<Eigen::Vector3d>& points, const std::vector<int>& face, double planarityTolerance) {
    const Eigen::Vector3d n = polygonAreaVector(points, face).normalized();
    return extrudesWhole(points, face, n, planarityTolerance) ? 1 : int(face.size()) - 2;
}

std::vector<ConvexPolyhedron> extrudeFace(const std::vector<Eigen::Vector3d>& points, const std::vector<int>& face,
                                          double thickness, double planarityTolerance, int visualVertexCount,
                                          const std::string& what) {
    const Eigen::Vector3d n = polygonAreaVector(points, face).normalized();
    if (extrudesWhole(points, face, n, planarityTolerance)) {
        try {
            return {extrudeConvexPolygon(points, face, n, thickness, visualVertexCount, what)};
        } catch (const InputError&) {
            // Flat within the body's tolerance but not within the prism's own (a small face
            // on a large body): triangles are exactly planar.
            if (face.size() == 3) throw;
        }
    }
    return extrudeTriangles(points, face, n, thickness, visualVertexCount, what);
}

} // namespace shatter::geometry
