#pragma once
// The check every split and fracture test makes: its parts carry the whole's mass, momentum and
// angular momentum (world frame, double precision).
#include <shatter/plugin/geometry/RigidState.h>

#include <gtest/gtest.h>

#include <vector>

namespace shatter::test {

// The size of the momentum terms summed: the scale errors are relative to (a whole's total can
// cancel to near zero while its parts' do not).
struct MomentumScales {
    double linear = 0, angular = 0;
};

// Mass to 1e-12 and momenta to 1e-9 of the scales, which it returns for coarser checks.
inline MomentumScales expectPartsConserveTheWhole(const geometry::RigidState& whole, const std::vector<geometry::RigidState>& parts) {
    double mass = 0, pScale = whole.linearMomentum().norm(), lScale = whole.angularMomentum().norm();
    Eigen::Vector3d p = Eigen::Vector3d::Zero(), l = Eigen::Vector3d::Zero();
    for (const auto& part : parts) {
        mass += part.mass;
        p += part.linearMomentum();
        l += part.angularMomentum();
        pScale += part.linearMomentum().norm();
        lScale += part.centre.cross(part.linearMomentum()).norm() + (part.inertia * part.angularVelocity).norm();
    }
    EXPECT_NEAR(mass, whole.mass, 1e-12 * whole.mass);
    EXPECT_LT((p - whole.linearMomentum()).norm(), 1e-9 * pScale);
    EXPECT_LT((l - whole.angularMomentum()).norm(), 1e-9 * lScale);
    return {pScale, lScale};
}

} // namespace shatter::test
