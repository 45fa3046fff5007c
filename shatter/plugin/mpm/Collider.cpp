#include <shatter/plugin/mpm/Collider.h>

#include <algorithm>
#include <cmath>

namespace shatter::mpm {

bool Collider::project(const Vec2& p, Vec2& v) const {
    if (signedDistance(p) > 0) return false;
    const Vec2 n = normal(p);
    const Vec2 wall = velocity(p);
    const Vec2 relative = v - wall;
    const double vn = relative.dot(n);
    if (vn >= 0) return true; // separating: leave it alone
    Vec2 tangential = relative - vn * n;
    const double vt = tangential.norm();
    if (friction_ > 0) {
        // Coulomb: the normal impulse |vn| buys at most μ|vn| of tangential speed.
        tangential = vt <= -friction_ * vn ? Vec2::Zero() : Vec2(tangential * (1 + friction_ * vn / vt));
    }
    v = wall + tangential;
    return true;
}

std::uint64_t collidersTouching(const ColliderList& colliders, const Box& box) {
    std::uint64_t touching = 0;
    for (size_t k = 0; k < std::min<size_t>(colliders.size(), 64); ++k)
        if (colliders[k]->mayTouch(box)) touching |= std::uint64_t(1) << k;
    return touching;
}

HalfPlaneCollider::HalfPlaneCollider(Vec2 point, Vec2 normal, double friction)
    : Collider(friction), point_(point), normal_(normal.normalized()) {}

bool HalfPlaneCollider::mayTouch(const Box& box) const {
    // The corner of the box deepest along −normal.
    const Vec2 deepest(normal_.x() > 0 ? box.min.x() : box.max.x(), normal_.y() > 0 ? box.min.y() : box.max.y());
    return signedDistance(deepest) <= 0;
}

double BoxCollider::signedDistance(const Vec2& p) const {
    const Vec2 centre = 0.5 * (box_.min + box_.max), half = 0.5 * (box_.max - box_.min);
    const Vec2 q = (p - centre).cwiseAbs() - half;
    const double outside = q.cwiseMax(0.0).norm();
    return outside + std::min(std::max(q.x(), q.y()), 0.0);
}

bool BoxCollider::mayTouch(const Box& box) const {
    // signedDistance rounds: a point a few ulps outside may count as inside.
    const double slack = 1e-9 * (1 + box_.min.cwiseAbs().maxCoeff() + box_.max.cwiseAbs().maxCoeff());
    return Box{box_.min - Vec2::Constant(slack), box_.max + Vec2::Constant(slack)}.overlaps(box);
}

Vec2 BoxCollider::normal(const Vec2& p) const {
    const Vec2 centre = 0.5 * (box_.min + box_.max), half = 0.5 * (box_.max - box_.min);
    const Vec2 d = p - centre;
    const Vec2 q = d.cwiseAbs() - half;
    if (q.x() > 0 || q.y() > 0) {
        // Outside: towards p from the nearest box point.
        const Vec2 nearest = d.cwiseMax(-half).cwiseMin(half);
        return (d - nearest).normalized();
    }
    // Inside: out through the nearest face (ties go to x, deterministically).
    if (q.x() >= q.y()) return Vec2(d.x() >= 0 ? 1 : -1, 0);
    return Vec2(0, d.y() >= 0 ? 1 : -1);
}

bool CircleCollider::mayTouch(const Box& box) const {
    return (center_.cwiseMax(box.min).cwiseMin(box.max) - center_).norm() <= radius_;
}

Vec2 CircleCollider::normal(const Vec2& p) const {
    const Vec2 d = p - center_;
    const double n = d.norm();
    return n > 0 ? Vec2(d / n) : Vec2(0, 1);
}

} // namespace shatter::mpm
