#pragma once
// Bullet constraints for joint boxes (source 000 §3.1).
#include "plugin/geometry/PhysicalMesh.h"

#include <BulletDynamics/ConstraintSolver/btTypedConstraint.h>
#include <BulletDynamics/Dynamics/btRigidBody.h>
#include <memory>

namespace shatter {

// The constraint for `box` between two bodies; `meshPose` places mesh coordinates (where the
// box is given) in the world, and the bodies must already be at their initial transforms.
std::unique_ptr<btTypedConstraint> makeJointConstraint(const geometry::JointBox& box, const btTransform& meshPose,
                                                       btRigidBody& a, btRigidBody& b);

} // namespace shatter
