#pragma once
// The outline of a 2D body: a rectangle, a circle or a simple polygon.
#include <shatter/plugin/mpm/Types.h>

#include <variant>
#include <vector>

namespace shatter::mpm {

struct RectShape {
    Vec2 min, max;
};
struct CircleShape {
    Vec2 center;
    double radius = 0;
};
struct PolygonShape {
    std::vector<Vec2> points; // either orientation, not closed (last != first), simple
};

class Shape {
public:
    Shape() : Shape(RectShape{Vec2::Zero(), Vec2::Zero()}) {}
    Shape(RectShape s) : shape_(std::move(s)) {}
    Shape(CircleShape s) : shape_(std::move(s)) {}
    Shape(PolygonShape s) : shape_(std::move(s)) {}

    // Closed set: points on the outline count as inside.
    bool contains(const Vec2& p) const;
    Box bounds() const;
    // The outline as a closed loop of vertices (a circle as `circleSegments` chords, which is
    // exact to 1 − cos(π/n) of the radius: 2e-5 for 512).
    std::vector<Vec2> outline(int circleSegments = 512) const;
    double area() const;

    const auto& variant() const { return shape_; }

private:
    std::variant<RectShape, CircleShape, PolygonShape> shape_;
};

// Twice the signed area of a closed loop (> 0 counter-clockwise).
double signedDoubleArea(const std::vector<Vec2>& loop);
// True when two edges of the closed loop that are not neighbours intersect.
bool selfIntersects(const std::vector<Vec2>& loop);
// True when segments [a, b] and [c, d] intersect (touching counts).
bool segmentsIntersect(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d);

} // namespace shatter::mpm
