// Triangles of a polygon must cover it exactly: inside it, as much area, same winding.
#include "demos/runner/PolygonTriangles.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

using shatter::demo::polygonTriangles;

namespace {

double area(const std::vector<Eigen::Vector3d>& p, const std::array<int, 3>& t) {
    return 0.5 * (p[size_t(t[1])] - p[size_t(t[0])]).cross(p[size_t(t[2])] - p[size_t(t[0])]).dot(Eigen::Vector3d::UnitZ());
}

} // namespace

TEST(PolygonTriangles, NonConvexPolygonIsCoveredByTrianglesInsideIt) {
    // An L of area 3 (three unit squares), counter-clockwise seen from +z, with a straight
    // corner (a vertex on an edge) at (1, 0).
    const std::vector<Eigen::Vector3d> l = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {2, 1, 0}, {1, 1, 0}, {1, 2, 0}, {0, 2, 0}};
    const auto triangles = polygonTriangles(l);
    double total = 0;
    for (const auto& t : triangles) {
        EXPECT_GE(area(l, t), 0) << "a triangle is wound the other way";
        total += area(l, t);
        // No triangle reaches into the L's missing square (1..2, 1..2).
        const Eigen::Vector3d c = (l[size_t(t[0])] + l[size_t(t[1])] + l[size_t(t[2])]) / 3;
        EXPECT_FALSE(c.x() > 1 && c.y() > 1);
    }
    EXPECT_NEAR(total, 3.0, 1e-12);
}

TEST(PolygonTriangles, TooFewCornersGiveNoTriangles) {
    EXPECT_TRUE(polygonTriangles({{0, 0, 0}, {1, 0, 0}}).empty());
    EXPECT_EQ(polygonTriangles({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}).size(), 1u);
}
