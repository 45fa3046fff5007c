#pragma once
// Joints from joint boxes (source 000 §3.1): the Bullet constraint a box makes between two
// bodies of an object, and the record the Plugin keeps of it.
#include <shatter/bullet_ext/Watched.h>
#include <shatter/plugin/geometry/PhysicalMesh.h>

#include <BulletDynamics/ConstraintSolver/btTypedConstraint.h>
#include <BulletDynamics/Dynamics/btRigidBody.h>
#include <memory>
#include <string>

namespace shatter {

class VisualBody;

// The constraint for `box` (given in the object's mesh coordinates) between two bodies of
// the object; meshToBodyA/B map mesh coordinates into each body's frame. Independent of where
// the bodies are now, so a joint can be rebuilt after a body's frame changed (a plastic dent
// moves its centre of mass). The constraint is a Watched<...> (Watched.h).
std::unique_ptr<btTypedConstraint> makeJointConstraint(const geometry::JointBox& box, btRigidBody& a,
                                                       const btTransform& meshToBodyA, btRigidBody& b,
                                                       const btTransform& meshToBodyB);

// A joint box's constraint in the world (fixed: btFixedConstraint, hinge: btHingeConstraint
// about the box's longest axis, ball: btPoint2PointConstraint at the box centre). Owned by
// the Plugin, which creates, rebuilds and removes it.
class Joint {
public:
    int id() const { return id_; }
    const std::string& name() const { return box_.name; }
    const geometry::JointBox& box() const { return box_; }
    btTypedConstraint& constraint() { return *constraint_; }
    const VisualBody& bodyA() const { return *bodyA_; }
    const VisualBody& bodyB() const { return *bodyB_; }
    // Bullet disabled it: its impulse passed BodySettings::jointBreakingImpulse.
    bool broken() const { return broken_; }

private:
    friend class Plugin;
    int id_ = -1;
    geometry::JointBox box_;
    WatchedPtr<btTypedConstraint> constraint_; // the application may delete it (Watched.h)
    VisualBody* bodyA_ = nullptr;
    VisualBody* bodyB_ = nullptr;
    bool broken_ = false;
};

} // namespace shatter
