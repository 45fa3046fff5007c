// Global ids of new vertices: one id per rest position within the snap tolerance, handed out
// in call order (source 000 §3.6), however many cells the look-up table holds.
#include <shatter/plugin/fracture/NewVertexIds.h>

#include <gtest/gtest.h>

#include <vector>

using namespace shatter::fracture;

namespace {
constexpr double kTolerance = 1e-7;
constexpr double kCell = 16.0 * kTolerance; // NewVertexIds' grid cell
} // namespace

// Twenty thousand points in distinct grid cells: more than the table starts with room for,
// so it grows on the way; every point keeps its id, and a point within the tolerance of one
// gets that id back, also when it lies in the neighbouring cell (the point on a cell border).
TEST(NewVertexIds, PointsWithinTheToleranceShareOneIdAsTheTableGrows) {
    NewVertexIds ids(100, kTolerance);
    std::vector<Eigen::Vector3d> points;
    for (int i = 0; i < 20000; ++i)
        points.emplace_back(double(i % 40) * 4.0 * kCell, double(i / 40 % 25) * 4.0 * kCell, double(i / 1000) * 4.0 * kCell);
    for (size_t i = 0; i < points.size(); ++i) EXPECT_EQ(ids.idAt(points[i]), 100 + int(i));
    EXPECT_EQ(ids.count(), 20000);

    const Eigen::Vector3d near(0.4 * kTolerance, -0.4 * kTolerance, 0.4 * kTolerance); // |near| < tolerance
    for (size_t i = 0; i < points.size(); i += 7) {
        EXPECT_EQ(ids.idAt(points[i] + near), 100 + int(i));
        EXPECT_EQ(ids.idAt(points[i] - near), 100 + int(i));
    }
    EXPECT_EQ(ids.count(), 20000); // nothing new

    // Farther than the tolerance from every point: new ids, in call order.
    const Eigen::Vector3d apart(0.0, 0.0, 2.0 * kTolerance);
    EXPECT_EQ(ids.idAt(points[5] + apart), 20100);
    EXPECT_EQ(ids.idAt(points[6] + apart), 20101);
    EXPECT_EQ(ids.idAt(points[5] + apart), 20100);
    EXPECT_EQ(ids.position(20100), points[5] + apart);
}
