#include <shatter/plugin/mpm/Shape.h>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace shatter::mpm {

namespace {

bool polygonContains(const std::vector<Vec2>& pts, const Vec2& p) {
    // Points on an edge count as inside, so that a polygon and a rectangle with the same
    // outline seed the same particles.
    bool inside = false;
    const size_t n = pts.size();
    for (size_t i = 0, j = n - 1; i < n; j = i++) {
        const Vec2& a = pts[j];
        const Vec2& b = pts[i];
        const double o = orient(a, b, p);
        const bool between = std::min(a.x(), b.x()) <= p.x() && p.x() <= std::max(a.x(), b.x()) &&
                             std::min(a.y(), b.y()) <= p.y() && p.y() <= std::max(a.y(), b.y());
        if (o == 0 && between) return true;
        if ((a.y() > p.y()) != (b.y() > p.y())) {
            const double x = a.x() + (p.y() - a.y()) * (b.x() - a.x()) / (b.y() - a.y());
            if (p.x() < x) inside = !inside;
        }
    }
    return inside;
}

} // namespace

bool Shape::contains(const Vec2& p) const {
    if (auto r = std::get_if<RectShape>(&shape_)) return Box{r->min, r->max}.contains(p);
    if (auto c = std::get_if<CircleShape>(&shape_)) return (p - c->center).squaredNorm() <= c->radius * c->radius;
    return polygonContains(std::get<PolygonShape>(shape_).points, p);
}

Box Shape::bounds() const {
    if (auto r = std::get_if<RectShape>(&shape_)) return {r->min, r->max};
    if (auto c = std::get_if<CircleShape>(&shape_))
        return {c->center - Vec2::Constant(c->radius), c->center + Vec2::Constant(c->radius)};
    const auto& pts = std::get<PolygonShape>(shape_).points;
    Box b{pts.front(), pts.front()};
    for (const Vec2& p : pts) {
        b.min = b.min.cwiseMin(p);
        b.max = b.max.cwiseMax(p);
    }
    return b;
}

std::vector<Vec2> Shape::outline(int circleSegments) const {
    if (auto r = std::get_if<RectShape>(&shape_))
        return {r->min, Vec2(r->max.x(), r->min.y()), r->max, Vec2(r->min.x(), r->max.y())};
    if (auto c = std::get_if<CircleShape>(&shape_)) {
        std::vector<Vec2> loop;
        for (int k = 0; k < circleSegments; ++k) {
            const double a = 2 * std::numbers::pi * k / circleSegments;
            loop.push_back(c->center + c->radius * Vec2(std::cos(a), std::sin(a)));
        }
        return loop;
    }
    return std::get<PolygonShape>(shape_).points;
}

double Shape::area() const {
    if (auto r = std::get_if<RectShape>(&shape_)) return (r->max - r->min).prod();
    if (auto c = std::get_if<CircleShape>(&shape_)) return std::numbers::pi * c->radius * c->radius;
    return 0.5 * std::abs(signedDoubleArea(std::get<PolygonShape>(shape_).points));
}

double signedDoubleArea(const std::vector<Vec2>& loop) {
    double a = 0;
    for (size_t i = 0, j = loop.size() - 1; i < loop.size(); j = i++)
        a += loop[j].x() * loop[i].y() - loop[i].x() * loop[j].y();
    return a;
}

bool segmentsIntersect(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d) {
    const double o1 = orient(a, b, c), o2 = orient(a, b, d), o3 = orient(c, d, a), o4 = orient(c, d, b);
    auto within = [](const Vec2& p, const Vec2& q, const Vec2& r) {
        return std::min(p.x(), q.x()) <= r.x() && r.x() <= std::max(p.x(), q.x()) && std::min(p.y(), q.y()) <= r.y() &&
               r.y() <= std::max(p.y(), q.y());
    };
    if (((o1 > 0 && o2 < 0) || (o1 < 0 && o2 > 0)) && ((o3 > 0 && o4 < 0) || (o3 < 0 && o4 > 0))) return true;
    return (o1 == 0 && within(a, b, c)) || (o2 == 0 && within(a, b, d)) || (o3 == 0 && within(c, d, a)) ||
           (o4 == 0 && within(c, d, b));
}

bool selfIntersects(const std::vector<Vec2>& loop) {
    const size_t n = loop.size();
    for (size_t i = 0; i < n; ++i)
        for (size_t j = i + 1; j < n; ++j) {
            const bool neighbours = j == i + 1 || (i == 0 && j == n - 1);
            if (neighbours) continue;
            if (segmentsIntersect(loop[i], loop[(i + 1) % n], loop[j], loop[(j + 1) % n])) return true;
        }
    return false;
}

} // namespace shatter::mpm
