#pragma once
// A rigid body's mass and motion in one frame, and what its parts inherit when it comes
// apart (a lattice piece splitting, a body fractured by a pattern): every part moves as the
// parent moved at the part's own centre of mass, so mass and linear and angular momentum add
// up to the parent's exactly (parallel-axis theorem), up to rounding.
#include <shatter/plugin/geometry/MassProperties.h>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace shatter::geometry {

struct RigidState {
    double mass = 0.0;
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero(); // about the centre, in the frame's axes
    Eigen::Vector3d velocity = Eigen::Vector3d::Zero();
    Eigen::Vector3d angularVelocity = Eigen::Vector3d::Zero();

    Eigen::Vector3d linearMomentum() const { return mass * velocity; }
    // About the frame's origin.
    Eigen::Vector3d angularMomentum() const { return centre.cross(linearMomentum()) + inertia * angularVelocity; }
};

// `mass` (in its own coordinates) seen through `transform`: centre moved, inertia turned.
// The rotation part is re-orthonormalised first: a pose from a single-precision engine is
// orthonormal only to about 1e-7, and the parallel-axis sums that make parts add up to their
// parent need an exact rotation.
MassProperties transformed(const MassProperties& mass, const Eigen::Isometry3d& transform);

// A body whose mass properties are `mass` (given in the frame of the velocities) moving with
// `velocity` (of its centre of mass) and `angularVelocity`.
RigidState rigidState(const MassProperties& mass, const Eigen::Vector3d& velocity, const Eigen::Vector3d& angularVelocity);

// The state a part with mass properties `part` (same frame as `parent`) takes from its parent:
// the parent's velocity at the part's centre of mass (v + ω × (c_part − c)) and the parent's ω.
RigidState partState(const RigidState& parent, const MassProperties& part);

} // namespace shatter::geometry
