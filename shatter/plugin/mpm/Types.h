#pragma once
// The small fixed-size math types every part of the 2D solver shares.
#include <Eigen/Core>
#include <Eigen/LU> // determinant()

namespace shatter::mpm {

using Vec2 = Eigen::Vector2d;
using Mat2 = Eigen::Matrix2d;

// Axis-aligned box in the plane; also the "region" of loads and fixed particles.
struct Box {
    Vec2 min = Vec2::Zero();
    Vec2 max = Vec2::Zero();

    bool contains(const Vec2& p) const {
        return p.x() >= min.x() && p.x() <= max.x() && p.y() >= min.y() && p.y() <= max.y();
    }
    bool overlaps(const Box& o) const {
        return min.x() <= o.max.x() && o.min.x() <= max.x() && min.y() <= o.max.y() && o.min.y() <= max.y();
    }
};

// Counter-clockwise perpendicular: the "above" side of a direction.
inline Vec2 leftNormal(const Vec2& d) { return Vec2(-d.y(), d.x()); }

// Twice the signed area of triangle (a, b, c): > 0 when a→b→c turns counter-clockwise.
inline double orient(const Vec2& a, const Vec2& b, const Vec2& c) {
    return (b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x());
}

} // namespace shatter::mpm
