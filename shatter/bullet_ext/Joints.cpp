#include <shatter/bullet_ext/Joints.h>

#include <shatter/bullet_ext/Convert.h>
#include <shatter/bullet_ext/Watched.h>

#include <BulletDynamics/ConstraintSolver/btFixedConstraint.h>
#include <BulletDynamics/ConstraintSolver/btHingeConstraint.h>
#include <BulletDynamics/ConstraintSolver/btPoint2PointConstraint.h>

namespace shatter {

std::unique_ptr<btTypedConstraint> makeJointConstraint(const geometry::JointBox& box, btRigidBody& a,
                                                       const btTransform& meshToBodyA, btRigidBody& b,
                                                       const btTransform& meshToBodyB) {
    // Bullet's hinge turns about the frame's z axis; the box's hinge axis is its axis 0.
    // A cyclic permutation of the columns keeps the frame a proper rotation.
    Eigen::Isometry3d frame = box.pose;
    if (box.type == geometry::JointType::Hinge) {
        const Eigen::Matrix3d r = box.pose.linear();
        frame.linear() << r.col(1), r.col(2), r.col(0);
    }
    const btTransform inA = meshToBodyA * toBullet(frame);
    const btTransform inB = meshToBodyB * toBullet(frame);
    switch (box.type) {
    case geometry::JointType::Hinge: return std::make_unique<Watched<btHingeConstraint>>(a, b, inA, inB);
    case geometry::JointType::Ball:
        return std::make_unique<Watched<btPoint2PointConstraint>>(a, b, inA.getOrigin(), inB.getOrigin());
    case geometry::JointType::Fixed: break;
    }
    return std::make_unique<Watched<btFixedConstraint>>(a, b, inA, inB);
}

} // namespace shatter
