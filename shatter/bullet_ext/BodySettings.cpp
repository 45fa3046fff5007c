#include <shatter/bullet_ext/BodySettings.h>

#include <shatter/plugin/common/SettingCheck.h>

namespace shatter {

void RigidBodySettings::check(const std::string& body) const {
    requireNonNegative(body, "friction", friction);
    requireNonNegative(body, "restitution", restitution);
    requireNonNegative(body, "rolling friction", rollingFriction);
    requireNonNegative(body, "spinning friction", spinningFriction);
    requireNonNegative(body, "linear damping", linearDamping);
    requireNonNegative(body, "angular damping", angularDamping);
    requireNonNegative(body, "collision margin", collisionMargin);
}

void RigidBodySettings::applyTo(btRigidBody::btRigidBodyConstructionInfo& info) const {
    info.m_friction = btScalar(friction);
    info.m_restitution = btScalar(restitution);
    info.m_rollingFriction = btScalar(rollingFriction);
    info.m_spinningFriction = btScalar(spinningFriction);
    info.m_linearDamping = btScalar(linearDamping);
    info.m_angularDamping = btScalar(angularDamping);
}

void BodySettings::check(const std::string& body) const {
    rigidBody.check(body);
    requireNonNegative(body, "joint breaking impulse", jointBreakingImpulse);
    fracture.check(body);
    if (fracture.enabled && fracture.mode == FractureMode::Shatter && deformation != Deformation::None)
        throw InputError("body '" + body + "': fracture needs deformation None (a rigid body), not a deformable one");
    tear.check(body);
    if (tear.enabled && deformation == Deformation::None)
        throw InputError("body '" + body +
                         "': tear needs deformation Soft or Plastic (a rigid body's primitives never move apart)");
    if (fracture.enabled && fracture.mode == FractureMode::Subdivide && deformation == Deformation::Soft)
        throw InputError("body '" + body + "': fracture mode Subdivide needs deformation None or Plastic, not Soft");
    if (deformation == Deformation::None) return;
    solver.check(body);
    plastic.check(body);
}

} // namespace shatter
