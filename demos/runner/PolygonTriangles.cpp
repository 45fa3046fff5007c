#include "demos/runner/PolygonTriangles.h"

#include <Eigen/Geometry>

namespace shatter::demo {

namespace {

std::vector<std::array<int, 3>> fan(int n) {
    std::vector<std::array<int, 3>> triangles;
    for (int i = 1; i + 1 < n; ++i) triangles.push_back({0, i, i + 1});
    return triangles;
}

double cross2(const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); }

bool inside(const Eigen::Vector2d& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c) {
    return cross2(b - a, p - a) >= 0 && cross2(c - b, p - b) >= 0 && cross2(a - c, p - c) >= 0;
}

} // namespace

std::vector<std::array<int, 3>> polygonTriangles(const std::vector<Eigen::Vector3d>& polygon) {
    const int n = int(polygon.size());
    if (n < 3) return {};
    if (n == 3) return {{0, 1, 2}};
    Eigen::Vector3d normal = Eigen::Vector3d::Zero();
    for (int i = 0; i < n; ++i) normal += polygon[size_t(i)].cross(polygon[size_t((i + 1) % n)]);
    if (!(normal.norm() > 0) || !normal.allFinite()) return fan(n);
    normal.normalize();
    // A basis of the plane with (u, v, normal) right-handed: the polygon is counter-clockwise in (u, v).
    const Eigen::Vector3d u = normal.unitOrthogonal(), v = normal.cross(u);
    std::vector<Eigen::Vector2d> flat;
    for (const auto& p : polygon) flat.emplace_back(p.dot(u), p.dot(v));

    std::vector<int> left(static_cast<size_t>(n));
    for (int i = 0; i < n; ++i) left[size_t(i)] = i;
    std::vector<std::array<int, 3>> triangles;
    int guard = 0;
    size_t i = 0;
    while (left.size() > 3) {
        if (++guard > 2 * n * n) return fan(n); // no ear found: not a simple polygon
        const size_t m = left.size();
        const int a = left[(i + m - 1) % m], b = left[i % m], c = left[(i + 1) % m];
        const Eigen::Vector2d &pa = flat[size_t(a)], &pb = flat[size_t(b)], &pc = flat[size_t(c)];
        // Convex corner; a straight one (a vertex on an edge, common on crack faces) is clipped
        // as a zero-area triangle, which just drops it.
        bool ear = cross2(pb - pa, pc - pb) >= 0;
        for (size_t k = 0; ear && k < m; ++k) {
            const int q = left[k];
            if (q != a && q != b && q != c && inside(flat[size_t(q)], pa, pb, pc)) ear = false;
        }
        if (ear) {
            triangles.push_back({a, b, c});
            left.erase(left.begin() + std::ptrdiff_t(i % m));
        } else {
            ++i;
        }
    }
    triangles.push_back({left[0], left[1], left[2]});
    return triangles;
}

} // namespace shatter::demo
