#include <shatter/plugin/common/InputError.h>
#include <shatter/plugin/fracture/Placement.h>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

using namespace shatter;
using namespace shatter::fracture;

TEST(Placement, MovesTheOriginToThePointTheAxisToTheNormalAndScales) {
    Placement p;
    p.point = {1.0, 2.0, 3.0};
    p.normal = {0.0, -2.0, 0.0};
    p.twist = 0.7;
    p.scale = 2.5;
    EXPECT_TRUE(p.apply(Eigen::Vector3d::Zero()).isApprox(p.point, 1e-15));
    EXPECT_TRUE((p.apply(Eigen::Vector3d::UnitZ()) - p.point).isApprox(Eigen::Vector3d(0, -2.5, 0), 1e-14));
    // The twist turns the pattern about the normal: x and y axes stay perpendicular to it.
    const Eigen::Vector3d x = p.apply(Eigen::Vector3d::UnitX()) - p.point;
    EXPECT_NEAR(x.norm(), 2.5, 1e-14);
    EXPECT_NEAR(x.dot(p.normal), 0.0, 1e-14);
    Placement q = p;
    q.twist = p.twist + 0.5;
    const Eigen::Vector3d xq = q.apply(Eigen::Vector3d::UnitX()) - q.point;
    EXPECT_NEAR(std::acos(x.dot(xq) / (x.norm() * xq.norm())), 0.5, 1e-12);
    EXPECT_NEAR(p.rotation().determinant(), 1.0, 1e-14);
}

TEST(Placement, TheNormalOppositeTheAxisIsStillARotation) {
    Placement p;
    p.normal = -Eigen::Vector3d::UnitZ();
    EXPECT_TRUE((p.rotation() * Eigen::Vector3d::UnitZ()).isApprox(-Eigen::Vector3d::UnitZ(), 1e-14));
    EXPECT_NEAR(p.rotation().determinant(), 1.0, 1e-14);
}

TEST(Placement, SeededTwistIsRepeatable) {
    EXPECT_EQ(seededTwist(42), seededTwist(42));
    EXPECT_NE(seededTwist(42), seededTwist(43));
    EXPECT_GE(seededTwist(1), 0.0);
    EXPECT_LT(seededTwist(1), 2.0 * 3.14159266);
}

TEST(Placement, NonFiniteOrZeroValuesAreErrorsNamingTheBody) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    Placement p;
    p.point.x() = nan;
    try {
        p.check("pane");
        FAIL();
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("body 'pane': fracture point must be finite"), std::string::npos)
            << e.what();
    }
    p = {};
    p.normal = Eigen::Vector3d::Zero();
    EXPECT_THROW(p.check("pane"), InputError);
    p = {};
    p.normal.y() = std::numeric_limits<double>::infinity();
    EXPECT_THROW(p.check("pane"), InputError);
    p = {};
    p.scale = 0.0;
    EXPECT_THROW(p.check("pane"), InputError);
    p = {};
    p.twist = nan;
    EXPECT_THROW(p.check("pane"), InputError);
}
