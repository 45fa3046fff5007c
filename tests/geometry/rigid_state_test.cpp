// Rigid states: mass properties seen through a rigid transform, and what parts of a body inherit.
#include <shatter/plugin/geometry/RigidState.h>

#include <gtest/gtest.h>

namespace shatter::geometry {
namespace {

// A solid box of the given size and density centred at `centre` (axis aligned).
MassProperties box(const Eigen::Vector3d& size, const Eigen::Vector3d& centre, double density) {
    MassProperties m;
    m.volume = size.prod();
    m.mass = density * m.volume;
    m.centerOfMass = centre;
    const Eigen::Vector3d s2 = size.cwiseProduct(size);
    m.inertia = (m.mass / 12.0 * Eigen::Vector3d(s2.y() + s2.z(), s2.x() + s2.z(), s2.x() + s2.y())).asDiagonal();
    return m;
}

TEST(RigidState, TransformedMovesTheCentreAndTurnsTheInertia) {
    const MassProperties m = box({2.0, 1.0, 0.5}, {0.3, -0.2, 0.1}, 700.0);
    Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
    t.linear() = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
    t.translation() = Eigen::Vector3d(5, -1, 2);
    const MassProperties w = transformed(m, t);
    EXPECT_EQ(w.mass, m.mass);
    EXPECT_LT((w.centerOfMass - t * m.centerOfMass).norm(), 1e-12);
    // The principal moments do not depend on the frame.
    const Eigen::Vector3d before = m.principal().moments, after = w.principal().moments;
    EXPECT_LT((before - after).norm(), 1e-12 * before.norm());
    // A rotation off orthonormal by single-precision rounding is made exact first.
    Eigen::Isometry3d rough = t;
    rough.linear() = rough.linear().cast<float>().cast<double>() * (1.0 + 1e-7);
    const MassProperties r = transformed(m, rough);
    EXPECT_LT((r.principal().moments - before).norm(), 1e-12 * before.norm());
}

TEST(RigidState, PartsOfASpinningBodyAddUpToItsMassAndMomenta) {
    // A bar of two boxes, moving and spinning: split at the joint, each half takes the velocity
    // of the whole at its own centre. Mass, linear and angular momentum (about the origin) add up.
    const MassProperties left = box({1.0, 0.4, 0.4}, {-0.5, 0, 0}, 1000.0);
    const MassProperties right = box({1.0, 0.4, 0.4}, {0.5, 0, 0}, 1000.0);
    MassProperties whole = left;
    whole += right;
    Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
    t.linear() = Eigen::AngleAxisd(1.1, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    t.translation() = Eigen::Vector3d(2, 3, -1);
    const RigidState parent = rigidState(transformed(whole, t), {1.0, -2.0, 0.5}, {0.3, -4.0, 2.5});
    const RigidState a = partState(parent, transformed(left, t));
    const RigidState b = partState(parent, transformed(right, t));
    EXPECT_NEAR(a.mass + b.mass, parent.mass, 1e-12 * parent.mass);
    EXPECT_LT((a.linearMomentum() + b.linearMomentum() - parent.linearMomentum()).norm(),
              1e-12 * parent.linearMomentum().norm());
    EXPECT_LT((a.angularMomentum() + b.angularMomentum() - parent.angularMomentum()).norm(),
              1e-12 * parent.angularMomentum().norm());
    // Each half moves as the whole did at its centre: v + ω × r.
    const Eigen::Vector3d r = a.centre - parent.centre;
    EXPECT_LT((a.velocity - (parent.velocity + parent.angularVelocity.cross(r))).norm(), 1e-12);
    EXPECT_EQ(a.angularVelocity, parent.angularVelocity);
}

} // namespace
} // namespace shatter::geometry
