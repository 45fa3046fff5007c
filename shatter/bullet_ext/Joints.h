#pragma once
// Bullet constraints for joint boxes (source 000 §3.1).
#include <shatter/plugin/geometry/PhysicalMesh.h>

#include <BulletDynamics/ConstraintSolver/btTypedConstraint.h>
#include <BulletDynamics/Dynamics/btRigidBody.h>
#include <memory>

namespace shatter {

// The constraint for `box` (given in the object's mesh coordinates) between two bodies of
// the object; meshToBodyA/B map mesh coordinates into each body's frame. Independent of where
// the bodies are now, so a joint can be rebuilt after a body's frame changed (a plastic dent
// moves its centre of mass).
std::unique_ptr<btTypedConstraint> makeJointConstraint(const geometry::JointBox& box, btRigidBody& a,
                                                       const btTransform& meshToBodyA, btRigidBody& b,
                                                       const btTransform& meshToBodyB);

} // namespace shatter
