// The picture camera must show everything it was asked to frame, fill the image with it,
// and keep Y up on screen.
#include "demos/runner/Camera.h"

#include <gtest/gtest.h>

using namespace shatter::demo;

namespace {

std::vector<Eigen::Vector3d> boxCorners(Eigen::Vector3d lo, Eigen::Vector3d hi) {
    std::vector<Eigen::Vector3d> c;
    for (int i = 0; i < 8; ++i) c.emplace_back(i & 1 ? hi.x() : lo.x(), i & 2 ? hi.y() : lo.y(), i & 4 ? hi.z() : lo.z());
    return c;
}

} // namespace

TEST(DemoCamera, FramedPointsAreInFrontAndInsideTheFreePartOfTheImage) {
    for (const auto& [lo, hi] : {std::pair{Eigen::Vector3d(-1, 0, -1), Eigen::Vector3d(1, 2, 1)},
                                 std::pair{Eigen::Vector3d(10, -3, 4), Eigen::Vector3d(60, 1, 5)},
                                 std::pair{Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0.01, 0.02, 0.01)}}) {
        const auto points = boxCorners(lo, hi);
        const Camera camera = Camera::framing(points, 1280, 720, 56);
        Eigen::Vector2d pmin(1e9, 1e9), pmax(-1e9, -1e9);
        for (const auto& p : points) {
            const Eigen::Vector3d q = camera.toCamera(p);
            ASSERT_GT(q.z(), camera.nearDepth());
            const Eigen::Vector2d px = camera.toPixel(q);
            pmin = pmin.cwiseMin(px);
            pmax = pmax.cwiseMax(px);
        }
        EXPECT_GE(pmin.x(), 0);
        EXPECT_LE(pmax.x(), 1280);
        EXPECT_GE(pmin.y(), 56);
        EXPECT_LE(pmax.y(), 720);
        // The limiting side spans most of the image.
        EXPECT_GT(std::max((pmax.x() - pmin.x()) / 1280, (pmax.y() - pmin.y()) / (720 - 56)), 0.8);
    }
}

TEST(DemoCamera, LooksFromTheFrontRightAndAboveWithYUpOnScreen) {
    const auto points = boxCorners({-1, 0, -1}, {1, 1, 1});
    const Camera camera = Camera::framing(points, 800, 600);
    EXPECT_GT(camera.eye().x(), 1);
    EXPECT_GT(camera.eye().y(), 1);
    EXPECT_GT(camera.eye().z(), 1);
    const auto low = camera.toPixel(camera.toCamera({0, 0, 0}));
    const auto high = camera.toPixel(camera.toCamera({0, 1, 0}));
    EXPECT_LT(high.y(), low.y());
    EXPECT_NEAR(high.x(), low.x(), 1e-6); // vertical lines stay vertical: no roll
    EXPECT_NEAR(camera.towardsEye().norm(), 1.0, 1e-12);
}

TEST(DemoCamera, NothingToFrameLooksAtTheOrigin) {
    const Camera camera = Camera::framing({}, 640, 480);
    const auto px = camera.toPixel(camera.toCamera(Eigen::Vector3d::Zero()));
    EXPECT_NEAR(px.x(), 320, 1e-6);
    EXPECT_NEAR(px.y(), 240, 1e-6);
}

TEST(DemoCamera, NonFinitePointsAreIgnored) {
    auto points = boxCorners({-1, 0, -1}, {1, 1, 1});
    const Camera reference = Camera::framing(points, 640, 480);
    points.emplace_back(std::numeric_limits<double>::quiet_NaN(), 0, 0);
    points.emplace_back(0, std::numeric_limits<double>::infinity(), 0);
    const Camera camera = Camera::framing(points, 640, 480);
    EXPECT_TRUE(camera.eye().isApprox(reference.eye()));
}
