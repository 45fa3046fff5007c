#include <shatter/bullet_ext/shape/HullFeatures.h>

#include <shatter/bullet_ext/Convert.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

namespace shatter {

void buildPolyhedralFeatures(const geometry::ConvexPolyhedron& p, btConvexPolyhedron& poly) {
    poly.m_vertices.reserve(int(p.vertices().size()));
    for (const auto& v : p.vertices()) poly.m_vertices.push_back(toBullet(v));
    poly.m_faces.resize(int(p.faces().size()));
    for (size_t f = 0; f < p.faces().size(); ++f) {
        btFace& face = poly.m_faces[int(f)];
        face.m_indices.reserve(int(p.faces()[f].size()));
        for (int i : p.faces()[f]) face.m_indices.push_back(i);
        const geometry::Plane& plane = p.planes()[f];
        face.m_plane[0] = btScalar(plane.normal.x());
        face.m_plane[1] = btScalar(plane.normal.y());
        face.m_plane[2] = btScalar(plane.normal.z());
        face.m_plane[3] = btScalar(-plane.offset); // Bullet's plane is n·x + w = 0
    }
    addUniqueEdges(p, poly);
    setInternalObjects(p, poly);
}

void addUniqueEdges(const geometry::ConvexPolyhedron& p, btConvexPolyhedron& poly) {
    // A closed polyhedron meets each edge twice, the second time the other way round: its
    // direction is then exactly the negated first one, known already, so it is skipped
    // (the same edges in the same order, for half the normalisations and comparisons).
    constexpr int kRemembered = 64;
    std::array<std::pair<int, int>, kRemembered> met;
    int metCount = 0;
    // Past kScanned known edges (a shard's hull has hundreds), only those whose |x| is within
    // the tolerance of the new edge's can match it either way round: a window of them sorted
    // by |x| (reused: a break builds thousands of child hulls, which stay below it).
    constexpr int kScanned = 16;
    thread_local std::vector<std::pair<double, int>> byX; // (|x|, index)
    byX.clear();
    auto same = [&](const Eigen::Vector3d& e, int u) {
        const Eigen::Vector3d v = toEigen(poly.m_uniqueEdges[u]);
        return (e - v).lpNorm<Eigen::Infinity>() < 1e-6 || (e + v).lpNorm<Eigen::Infinity>() < 1e-6;
    };
    auto known = [&](const Eigen::Vector3d& e) {
        if (poly.m_uniqueEdges.size() < kScanned) {
            for (int u = 0; u < poly.m_uniqueEdges.size(); ++u)
                if (same(e, u)) return true;
            return false;
        }
        if (byX.empty()) {
            for (int u = 0; u < poly.m_uniqueEdges.size(); ++u) byX.emplace_back(std::abs(poly.m_uniqueEdges[u].x()), u);
            std::sort(byX.begin(), byX.end());
        }
        const double x = std::abs(e.x());
        for (auto u = std::lower_bound(byX.begin(), byX.end(), std::pair(x - 1e-6, -1));
             u != byX.end() && u->first <= x + 1e-6; ++u)
            if (same(e, u->second)) return true;
        return false;
    };
    for (const auto& face : p.faces())
        for (size_t k = 0; k < face.size(); ++k) {
            const int a = face[k], b = face[(k + 1) % face.size()];
            if (std::find(met.begin(), met.begin() + metCount, std::pair(b, a)) != met.begin() + metCount) continue;
            if (metCount < kRemembered) met[size_t(metCount++)] = {a, b};
            const Eigen::Vector3d e = (p.vertices()[b] - p.vertices()[a]).normalized();
            if (known(e)) continue;
            poly.m_uniqueEdges.push_back(toBullet(e));
            if (byX.empty()) continue;
            const int u = poly.m_uniqueEdges.size() - 1;
            const std::pair<double, int> key(std::abs(poly.m_uniqueEdges[u].x()), u);
            byX.insert(std::upper_bound(byX.begin(), byX.end(), key), key);
        }
}

btScalar innerRadius(const geometry::ConvexPolyhedron& p, const Eigen::Vector3d& c) {
    double radius = std::numeric_limits<double>::infinity();
    for (const auto& plane : p.planes()) radius = std::min(radius, plane.offset - plane.normal.dot(c));
    return btScalar(std::max(radius, 0.0));
}

// Bullet's initialize() searches for the inner box with up to 2048 containment tests (75 µs
// per primitive); here the bounding box, scaled about the centroid until it fits behind every
// face, is found in one pass.
void setInternalObjects(const geometry::ConvexPolyhedron& p, btConvexPolyhedron& poly) {
    const Eigen::Vector3d c = p.massProperties(1.0).centerOfMass;
    const Eigen::Vector3d half = 0.5 * p.bounds().extent();
    double scale = 1.0;
    for (const auto& plane : p.planes()) {
        const double inside = plane.offset - plane.normal.dot(c); // > 0: c is interior
        const double reach = plane.normal.cwiseAbs().dot(half);
        if (reach > 0) scale = std::min(scale, inside / reach);
    }
    poly.m_localCenter = toBullet(c);
    poly.m_radius = innerRadius(p, c);
    poly.m_extents = toBullet(Eigen::Vector3d(std::max(scale, 0.0) * half));
    poly.mC = toBullet(Eigen::Vector3d(p.bounds().max + p.bounds().min));
    poly.mE = toBullet(p.bounds().extent());
}

} // namespace shatter
