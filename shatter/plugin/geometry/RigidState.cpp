#include <shatter/plugin/geometry/RigidState.h>

namespace shatter::geometry {

MassProperties transformed(const MassProperties& mass, const Eigen::Isometry3d& transform) {
    const Eigen::Matrix3d r = Eigen::Quaterniond(transform.linear()).normalized().toRotationMatrix();
    MassProperties out = mass;
    out.centerOfMass = r * mass.centerOfMass + transform.translation();
    out.inertia = r * mass.inertia * r.transpose();
    return out;
}

RigidState rigidState(const MassProperties& mass, const Eigen::Vector3d& velocity, const Eigen::Vector3d& angularVelocity) {
    RigidState s;
    s.mass = mass.mass;
    s.centre = mass.centerOfMass;
    s.inertia = mass.inertia;
    s.velocity = velocity;
    s.angularVelocity = angularVelocity;
    return s;
}

RigidState partState(const RigidState& parent, const MassProperties& part) {
    return rigidState(part, parent.velocity + parent.angularVelocity.cross(part.centerOfMass - parent.centre),
                      parent.angularVelocity);
}

} // namespace shatter::geometry
