#pragma once
// Where a fracture pattern is applied (source 000 §3.6): in the body's rest (mesh)
// coordinates, the pattern's origin at the impact point, its axis +z turned to the impact
// normal (pointing into the body), turned by `twist` about that axis and scaled.
#include <shatter/plugin/geometry/PhysicalMesh.h>

#include <Eigen/Geometry>
#include <cstdint>
#include <string>

namespace shatter::fracture {

struct Placement {
    Eigen::Vector3d point = Eigen::Vector3d::Zero();
    Eigen::Vector3d normal = Eigen::Vector3d::UnitZ(); // any length > 0; into the body
    double twist = 0.0;                                // radians about the normal
    double scale = 1.0;                                // pattern units → metres

    // Point and normal finite, normal non-zero, twist finite, scale positive and finite;
    // errors name `body`.
    void check(const std::string& body) const;
    // Rotation taking the pattern's axes to the body's (z to the unit normal, then twist).
    Eigen::Matrix3d rotation() const;
    // Pattern coordinates → body rest coordinates: x ↦ point + scale·R·x.
    Eigen::Vector3d apply(const Eigen::Vector3d& patternPoint) const { return point + scale * (rotation() * patternPoint); }
};

// A twist in [0, 2π) drawn from `seed` (same seed ⇒ same twist), so that repeated impacts
// do not show the same pattern.
double seededTwist(std::uint64_t seed);

// For thin sheets: the body's thinnest axis (the principal axis of largest moment of
// inertia), signed to point along `impactNormal`. A glass pattern placed with this normal
// cuts straight through the sheet wherever the impact came from.
Eigen::Vector3d thinnestAxis(const geometry::PhysicalMesh& body, const Eigen::Vector3d& impactNormal);

} // namespace shatter::fracture
