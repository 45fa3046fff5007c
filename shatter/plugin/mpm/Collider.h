#pragma once
// Static obstacles the body collides with, seen through their signed distance: negative
// inside, with an outward unit normal. Grid nodes and particles inside a collider lose the
// velocity component that moves into it (eq. 11 of 001), with optional Coulomb friction.
#include <shatter/plugin/mpm/Types.h>

#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

namespace shatter::mpm {

class Collider {
public:
    explicit Collider(double friction = 0) : friction_(friction) {}
    virtual ~Collider() = default;

    virtual double signedDistance(const Vec2& p) const = 0;
    virtual Vec2 normal(const Vec2& p) const = 0; // outward, unit length
    // Velocity of the collider surface at p (m/s); static colliders return zero.
    virtual Vec2 velocity(const Vec2&) const { return Vec2::Zero(); }
    double friction() const { return friction_; }

    // Applies the contact rule to a velocity at p; returns true when p is inside.
    bool project(const Vec2& p, Vec2& v) const;
    // False only when no point of `box` is inside: the solver then skips the collider for
    // all the particles in the box. The default cannot tell and says true.
    virtual bool mayTouch(const Box&) const { return true; }

private:
    double friction_; // Coulomb coefficient μ: tangential speed drops by μ·|normal speed|
};

// The solid side of the line through `point` opposite to `normal` (e.g. the ground).
class HalfPlaneCollider final : public Collider {
public:
    HalfPlaneCollider(Vec2 point, Vec2 normal, double friction = 0);
    double signedDistance(const Vec2& p) const override { return (p - point_).dot(normal_); }
    Vec2 normal(const Vec2&) const override { return normal_; }
    bool mayTouch(const Box& box) const override;
    const Vec2& point() const { return point_; }
    const Vec2& planeNormal() const { return normal_; }

private:
    Vec2 point_, normal_;
};

class BoxCollider final : public Collider {
public:
    BoxCollider(Box box, double friction = 0) : Collider(friction), box_(box) {}
    double signedDistance(const Vec2& p) const override;
    Vec2 normal(const Vec2& p) const override;
    bool mayTouch(const Box& box) const override;
    const Box& box() const { return box_; }

private:
    Box box_;
};

class CircleCollider final : public Collider {
public:
    CircleCollider(Vec2 center, double radius, double friction = 0)
        : Collider(friction), center_(center), radius_(radius) {}
    double signedDistance(const Vec2& p) const override { return (p - center_).norm() - radius_; }
    Vec2 normal(const Vec2& p) const override;
    bool mayTouch(const Box& box) const override;
    const Vec2& center() const { return center_; }
    double radius() const { return radius_; }

private:
    Vec2 center_;
    double radius_;
};

// Any object that can report a signed distance and normal, e.g. a Bullet collision object
// seen through btGjkEpaSolver2::SignedDistance in bullet_ext. The functions must be
// thread-safe: the solver calls them from several threads at once.
class SignedDistanceCollider final : public Collider {
public:
    using DistanceFunction = std::function<double(const Vec2&)>;
    using NormalFunction = std::function<Vec2(const Vec2&)>;
    SignedDistanceCollider(DistanceFunction distance, NormalFunction normal, double friction = 0)
        : Collider(friction), distance_(std::move(distance)), normal_(std::move(normal)) {}
    double signedDistance(const Vec2& p) const override { return distance_(p); }
    Vec2 normal(const Vec2& p) const override { return normal_(p); }

private:
    DistanceFunction distance_;
    NormalFunction normal_;
};

using ColliderList = std::vector<std::shared_ptr<const Collider>>;

// Which colliders may touch a point of `box` (Collider::mayTouch): bit k for colliders[k].
// Only the first 64 have a bit; the later ones are always tested (see mustTest).
std::uint64_t collidersTouching(const ColliderList& colliders, const Box& box);
// Whether colliders[k] needs testing under a mask from collidersTouching.
inline bool mustTest(std::uint64_t touching, size_t k) { return k >= 64 || (touching >> k & 1); }
// Whether any collider needs testing under that mask.
inline bool anyToTest(std::uint64_t touching, const ColliderList& colliders) {
    return touching != 0 || colliders.size() > 64;
}

} // namespace shatter::mpm
