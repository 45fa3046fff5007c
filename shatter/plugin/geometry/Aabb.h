#pragma once
#include <Eigen/Core>
#include <limits>

namespace shatter::geometry {

// Axis-aligned box. An empty box has min > max and grows with extend().
struct Aabb {
    Eigen::Vector3d min = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
    Eigen::Vector3d max = Eigen::Vector3d::Constant(-std::numeric_limits<double>::infinity());

    bool empty() const { return (min.array() > max.array()).any(); }
    void extend(const Eigen::Vector3d& p) { min = min.cwiseMin(p); max = max.cwiseMax(p); }
    void extend(const Aabb& b) { min = min.cwiseMin(b.min); max = max.cwiseMax(b.max); }
    Aabb inflated(double r) const { return {min.array() - r, max.array() + r}; }
    // Written per axis, not as Eigen array comparisons: that form was not inlined where the
    // fracture's cutting asks the outer cells' tree (40 k calls of ~17 instructions a break).
    bool overlaps(const Aabb& b) const {
        return min.x() <= b.max.x() && min.y() <= b.max.y() && min.z() <= b.max.z() &&
               b.min.x() <= max.x() && b.min.y() <= max.y() && b.min.z() <= max.z();
    }
    Eigen::Vector3d center() const { return 0.5 * (min + max); }
    Eigen::Vector3d extent() const { return max - min; }
    double diagonal() const { return empty() ? 0.0 : extent().norm(); }
};

} // namespace shatter::geometry
