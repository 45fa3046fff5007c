#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <shatter/plugin/geometry/FaceList.h>

#include <vector>

namespace shatter::geometry {

// Mass, centre of mass and inertia tensor of a solid, exact for polyhedra.
// SI units: kg, m, kg·m². The inertia tensor is taken about the centre of mass,
// in the same axes as the vertices it was computed from.
struct MassProperties {
    double volume = 0.0;
    double mass = 0.0;
    Eigen::Vector3d centerOfMass = Eigen::Vector3d::Zero();
    Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();

    // Adds another solid (parallel-axis theorem). Overlapping volume counts twice,
    // which is what the particle-per-primitive model assumes.
    MassProperties& operator+=(const MassProperties& other);

    // Principal frame: rotation whose columns are the principal axes (a proper
    // rotation, det = +1) and the principal moments in ascending order.
    struct Principal {
        Eigen::Matrix3d axes;
        Eigen::Vector3d moments;
    };
    Principal principal() const;
};

// Exact mass properties of a closed polyhedron with outward-oriented planar faces
// (each face a polygon of vertex indices, counter-clockwise seen from outside).
MassProperties polyhedronMassProperties(const std::vector<Eigen::Vector3d>& vertices,
                                        const std::vector<std::vector<int>>& faces, double density);
MassProperties polyhedronMassProperties(const std::vector<Eigen::Vector3d>& vertices, const FaceList& faces,
                                        double density);

} // namespace shatter::geometry
