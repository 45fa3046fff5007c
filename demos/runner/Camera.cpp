#include "demos/runner/Camera.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace shatter::demo {

namespace {

constexpr double kAzimuth = 35.0 * std::numbers::pi / 180;   // from +Z towards +X
constexpr double kElevation = 24.0 * std::numbers::pi / 180; // above the horizon
constexpr double kFill = 0.84;                                // share of the free image the scene spans

} // namespace

Camera Camera::framing(const std::vector<Eigen::Vector3d>& points, int width, int height, int topMargin) {
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(INFINITY), hi = Eigen::Vector3d::Constant(-INFINITY);
    for (const auto& p : points)
        if (p.allFinite()) {
            lo = lo.cwiseMin(p);
            hi = hi.cwiseMax(p);
        }
    if (!(lo.array() <= hi.array()).all()) lo = hi = Eigen::Vector3d::Zero();
    const Eigen::Vector3d target = 0.5 * (lo + hi);
    const double radius = std::max(0.5 * (hi - lo).norm(), 0.05);

    Camera c;
    const Eigen::Vector3d back(std::sin(kAzimuth) * std::cos(kElevation), std::sin(kElevation),
                               std::cos(kAzimuth) * std::cos(kElevation));
    // Far enough that the bounding sphere fits a 30° field of view; the zoom below then
    // tightens the framing to the actual projections.
    const double distance = radius / std::sin(15.0 * std::numbers::pi / 180);
    c.eye_ = target + distance * back;
    c.forward_ = -back;
    c.right_ = c.forward_.cross(Eigen::Vector3d::UnitY()).normalized();
    c.up_ = c.right_.cross(c.forward_);
    c.near_ = 1e-3 * distance;

    // Zoom and shift the image centre (an off-axis projection, not a rotation) so the
    // projected points fill the free part of the image.
    Eigen::Vector2d pmin = Eigen::Vector2d::Constant(INFINITY), pmax = Eigen::Vector2d::Constant(-INFINITY);
    for (const auto& p : points) {
        if (!p.allFinite()) continue;
        const Eigen::Vector3d q = c.toCamera(p);
        const Eigen::Vector2d s(q.x() / q.z(), q.y() / q.z());
        pmin = pmin.cwiseMin(s);
        pmax = pmax.cwiseMax(s);
    }
    if (!(pmin.array() <= pmax.array()).all()) pmin = pmax = Eigen::Vector2d::Zero();
    const double freeHeight = std::max(1, height - topMargin);
    const Eigen::Vector2d span = (pmax - pmin).cwiseMax(1e-6);
    const double halfFov = std::tan(15.0 * std::numbers::pi / 180);
    c.focal_ = std::min({kFill * width / span.x(), kFill * freeHeight / span.y(), 4.0 * freeHeight / halfFov});
    const Eigen::Vector2d mid = 0.5 * (pmin + pmax);
    c.centre_ = Eigen::Vector2d(0.5 * width - c.focal_ * mid.x(), topMargin + 0.5 * freeHeight + c.focal_ * mid.y());
    return c;
}

Eigen::Vector3d Camera::toCamera(const Eigen::Vector3d& world) const {
    const Eigen::Vector3d d = world - eye_;
    return {d.dot(right_), d.dot(up_), d.dot(forward_)};
}

Eigen::Vector2d Camera::toPixel(const Eigen::Vector3d& q) const {
    return {centre_.x() + focal_ * q.x() / q.z(), centre_.y() - focal_ * q.y() / q.z()};
}

Eigen::Vector3d Camera::ray(const Eigen::Vector2d& pixel) const {
    return right_ * ((pixel.x() - centre_.x()) / focal_) - up_ * ((pixel.y() - centre_.y()) / focal_) + forward_;
}

} // namespace shatter::demo
