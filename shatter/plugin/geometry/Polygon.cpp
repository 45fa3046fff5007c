#include <shatter/plugin/geometry/Polygon.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <numbers>

namespace shatter::geometry {

namespace {

// Coordinates in a plane perpendicular to unitNormal, with (u, v, normal) right-handed so
// that counter-clockwise about the normal stays counter-clockwise in the plane.
std::vector<Eigen::Vector2d> projectToPlane(const std::vector<Eigen::Vector3d>& points, const std::vector<int>& polygon,
                                            const Eigen::Vector3d& unitNormal) {
    int smallest = 0;
    unitNormal.cwiseAbs().minCoeff(&smallest);
    const Eigen::Vector3d u = unitNormal.cross(Eigen::Vector3d::Unit(smallest)).normalized();
    const Eigen::Vector3d v = unitNormal.cross(u);
    std::vector<Eigen::Vector2d> out;
    out.reserve(polygon.size());
    const Eigen::Vector3d& origin = points[polygon.front()];
    for (int i : polygon) {
        const Eigen::Vector3d d = points[i] - origin;
        out.emplace_back(d.dot(u), d.dot(v));
    }
    return out;
}

double cross2(const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); }

// Relative sine below which a corner counts as straight.
constexpr double kStraightSine = 1e-9;

} // namespace

Eigen::Vector3d polygonAreaVector(const std::vector<Eigen::Vector3d>& points, const std::vector<int>& polygon) {
    Eigen::Vector3d n = Eigen::Vector3d::Zero();
    if (polygon.size() < 3) return n;
    const Eigen::Vector3d& origin = points[polygon.front()];
    for (size_t i = 1; i + 1 < polygon.size(); ++i)
        n += (points[polygon[i]] - origin).cross(points[polygon[i + 1]] - origin);
    return n;
}

PolygonDefect cleanPolygon(const std::vector<Eigen::Vector3d>& points, std::vector<int>& polygon,
                           double minNormalLength, bool mergeCoincident) {
    auto same = [&](int a, int b) { return a == b || (mergeCoincident && points[a] == points[b]); };
    std::vector<int> kept;
    kept.reserve(polygon.size());
    for (int v : polygon)
        if (kept.empty() || !same(kept.back(), v)) kept.push_back(v);
    while (kept.size() > 1 && same(kept.back(), kept.front())) kept.pop_back();
    polygon = std::move(kept);
    if (polygon.size() < 3) return PolygonDefect::TooFewVertices;
    std::vector<int> sorted = polygon;
    std::sort(sorted.begin(), sorted.end());
    if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end()) return PolygonDefect::RepeatedVertex;
    if (!(polygonAreaVector(points, polygon).norm() > minNormalLength)) return PolygonDefect::ZeroArea;
    return PolygonDefect::Kept;
}

double planarityError(const std::vector<Eigen::Vector3d>& points, const std::vector<int>& polygon,
                      const Eigen::Vector3d& unitNormal) {
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (int i : polygon) centroid += points[i];
    centroid /= double(polygon.size());
    double error = 0.0;
    for (int i : polygon) error = std::max(error, std::abs(unitNormal.dot(points[i] - centroid)));
    return error;
}

bool isConvexPolygon(const std::vector<Eigen::Vector3d>& points, const std::vector<int>& polygon,
                     const Eigen::Vector3d& unitNormal) {
    const std::vector<Eigen::Vector2d> q = projectToPlane(points, polygon, unitNormal);
    const size_t n = q.size();
    double turning = 0.0;
    for (size_t i = 0; i < n; ++i) {
        const Eigen::Vector2d e1 = q[i] - q[(i + n - 1) % n];
        const Eigen::Vector2d e2 = q[(i + 1) % n] - q[i];
        const double c = cross2(e1, e2);
        const double d = e1.dot(e2);
        const double scale = e1.norm() * e2.norm();
        if (c < -kStraightSine * scale) return false;          // right turn: concave corner
        if (std::abs(c) <= kStraightSine * scale && d < 0.0) return false; // spike: edge turns back
        turning += std::atan2(c, d);
    }
    // All left turns still allow a star that winds twice; a convex polygon turns once.
    return std::abs(turning - 2.0 * std::numbers::pi) < 1e-6;
}

namespace {

bool insideOrOnTriangle(const Eigen::Vector2d& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                        const Eigen::Vector2d& c, double eps) {
    return cross2(b - a, p - a) >= -eps && cross2(c - b, p - b) >= -eps && cross2(a - c, p - c) >= -eps;
}

class EarClipper {
public:
    explicit EarClipper(std::vector<Eigen::Vector2d> q) : q_(std::move(q)) {
        Eigen::Vector2d lo = q_.front(), hi = q_.front();
        for (const auto& p : q_) {
            lo = lo.cwiseMin(p);
            hi = hi.cwiseMax(p);
        }
        const double size2 = (hi - lo).squaredNorm();
        areaEps_ = 1e-12 * size2;
        for (size_t i = 0; i < q_.size(); ++i) ring_.push_back(int(i));
    }

    // Local vertex triples, counter-clockwise.
    std::vector<std::array<int, 3>> run() {
        std::vector<std::array<int, 3>> out;
        while (ring_.size() >= 3) {
            const int k = chooseEar();
            if (k < 0) break; // only a straight remnant of zero area is left
            const size_t n = ring_.size();
            if (area2(k) > areaEps_)
                out.push_back({ring_[(k + n - 1) % n], ring_[k], ring_[(k + 1) % n]});
            ring_.erase(ring_.begin() + k);
        }
        return out;
    }

private:
    double area2(int k) const {
        const size_t n = ring_.size();
        const Eigen::Vector2d& a = q_[ring_[(k + n - 1) % n]];
        const Eigen::Vector2d& b = q_[ring_[k]];
        const Eigen::Vector2d& c = q_[ring_[(k + 1) % n]];
        return cross2(b - a, c - b);
    }

    bool isEar(int k) const {
        if (!(area2(k) > areaEps_)) return false;
        const size_t n = ring_.size();
        const int ia = ring_[(k + n - 1) % n], ib = ring_[k], ic = ring_[(k + 1) % n];
        // A vertex on the cut a–c (or inside) would be left out or cut through.
        for (int j : ring_) {
            if (j == ia || j == ib || j == ic) continue;
            if (insideOrOnTriangle(q_[j], q_[ia], q_[ib], q_[ic], areaEps_)) return false;
        }
        return true;
    }

    // Ear with the best shape (area over squared perimeter) for small polygons, the
    // first ear for large ones (keeps clipping quadratic). Falls back to the most convex
    // corner when round-off or a non-simple projection leaves no clean ear, and to a
    // straight corner (dropped without a triangle) when nothing has area.
    int chooseEar() const {
        const int n = int(ring_.size());
        int best = -1;
        double bestQuality = -1.0;
        for (int k = 0; k < n; ++k) {
            if (!isEar(k)) continue;
            if (n > 64) return k;
            const double quality = area2(k) / perimeter2(k);
            if (quality > bestQuality) {
                bestQuality = quality;
                best = k;
            }
        }
        if (best >= 0) return best;
        double bestArea = areaEps_;
        for (int k = 0; k < n; ++k)
            if (area2(k) > bestArea) {
                bestArea = area2(k);
                best = k;
            }
        if (best >= 0) return best;
        return n > 3 ? 0 : -1;
    }

    double perimeter2(int k) const {
        const size_t n = ring_.size();
        const Eigen::Vector2d& a = q_[ring_[(k + n - 1) % n]];
        const Eigen::Vector2d& b = q_[ring_[k]];
        const Eigen::Vector2d& c = q_[ring_[(k + 1) % n]];
        const double p = (b - a).norm() + (c - b).norm() + (a - c).norm();
        return p * p;
    }

    std::vector<Eigen::Vector2d> q_;
    std::vector<int> ring_;
    double areaEps_ = 0.0;
};

} // namespace

std::vector<std::array<int, 3>> triangulatePolygon(const std::vector<Eigen::Vector3d>& points,
                                                   const std::vector<int>& polygon, const Eigen::Vector3d& unitNormal) {
    std::vector<std::array<int, 3>> triangles;
    if (polygon.size() < 3) return triangles;
    for (const auto& t : EarClipper(projectToPlane(points, polygon, unitNormal)).run())
        triangles.push_back({polygon[t[0]], polygon[t[1]], polygon[t[2]]});
    return triangles;
}

} // namespace shatter::geometry
