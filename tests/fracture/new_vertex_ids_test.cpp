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

// A point whose tolerance box lies inside one grid cell is looked up in that cell alone, one
// on a cell border in every cell the box touches: an id made by a look-up across the border is
// found by one inside a cell and the other way round, and the first cell searched wins.
TEST(NewVertexIds, IdsMadeInsideACellAndOnItsBorderFindEachOther) {
    NewVertexIds ids(0, kTolerance);
    const Eigen::Vector3d inside(0.5 * kCell, 0.5 * kCell, 0.5 * kCell);           // box within one cell
    const Eigen::Vector3d border(kCell + 0.5 * kTolerance, 0.5 * kCell, 0.5 * kCell); // box across x = kCell
    EXPECT_EQ(ids.idAt(inside), 0);
    EXPECT_EQ(ids.idAt(inside + Eigen::Vector3d(0.0, 0.9 * kTolerance, 0.0)), 0);
    EXPECT_EQ(ids.idAt(inside + Eigen::Vector3d(0.0, 1.1 * kTolerance, 0.0)), 1); // farther: new
    EXPECT_EQ(ids.idAt(border), 2);
    // In the cell below the border, its box inside that cell, made with the border point's
    // cells searched (it is farther than the tolerance from it).
    const Eigen::Vector3d below = border - Eigen::Vector3d(1.4 * kTolerance, 0.0, 0.0);
    EXPECT_EQ(ids.idAt(below), 3); // 1.4 tolerances from the border point: new
    EXPECT_EQ(ids.idAt(border + Eigen::Vector3d(0.3 * kTolerance, 0.0, 0.0)), 2); // box across the border
    EXPECT_EQ(ids.idAt(border + Eigen::Vector3d(0.7 * kTolerance, 0.0, 0.0)), 2); // box inside the cell above
    // Made and found with boxes inside the cell above the border.
    const Eigen::Vector3d above = border + Eigen::Vector3d(2.0 * kTolerance, 0.0, 0.0);
    EXPECT_EQ(ids.idAt(above), 4);
    EXPECT_EQ(ids.idAt(above - Eigen::Vector3d(0.9 * kTolerance, 0.0, 0.0)), 4);
    // Both 2 and 3 are within the tolerance of this one: the cells are searched lowest first,
    // so 3 (below the border) is the one found (the order every look-up has always had).
    EXPECT_EQ(ids.idAt(border - Eigen::Vector3d(0.7 * kTolerance, 0.0, 0.0)), 3);
    EXPECT_EQ(ids.count(), 5);
}
