// Visual-mesh welding (source 000 §3.4): each visual vertex is the average of the primitive
// vertices that carry its id.
#include <shatter/plugin/geometry/PhysicalMesh.h>
#include <shatter/plugin/geometry/VisualMesh.h>

#include "MeshFixtures.h"

#include <gtest/gtest.h>

#include <random>
#include <stdexcept>

using namespace shatter::geometry;
using shatter::test::FaceMesh;

namespace {

PhysicalMesh extrudedGrid() {
    const FaceMesh grid = shatter::test::quadGrid(4, 3, 0.25);
    PhysicalMeshSettings s;
    s.thickness = 0.02;
    return buildPhysicalMesh("grid", grid.positions, grid.faces, s);
}

// Every primitive moved by its own random rigid motion of size ~1e-3 (rotation angle and
// translation), about its centroid.
std::vector<ConvexPolyhedron> jiggled(const std::vector<ConvexPolyhedron>& primitives, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    std::vector<ConvexPolyhedron> out;
    for (const auto& p : primitives) {
        const Eigen::Vector3d c = p.bounds().center();
        const Eigen::Vector3d axis = Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized();
        const Eigen::Isometry3d motion = Eigen::Translation3d(1e-3 * Eigen::Vector3d(u(rng), u(rng), u(rng))) *
                                         Eigen::Translation3d(c) * Eigen::AngleAxisd(1e-3 * u(rng), axis) *
                                         Eigen::Translation3d(-c);
        out.push_back(p.transformed(motion));
    }
    return out;
}

} // namespace

TEST(VertexWelder, AtRestGivesTheInputPositionsExactly) {
    const PhysicalMesh mesh = extrudedGrid();
    const VertexWelder welder(mesh.primitives, int(mesh.visual.positions.size()));
    std::vector<Eigen::Vector3d> positions;
    welder.weld(mesh.primitives, Eigen::Isometry3d::Identity(), positions);
    ASSERT_EQ(positions.size(), mesh.visual.positions.size());
    for (size_t i = 0; i < positions.size(); ++i) EXPECT_EQ(positions[i], mesh.visual.positions[i]) << i; // bitwise

    // In another frame: the transformed input, to round-off of one transform (1e-15 × size).
    const Eigen::Isometry3d t = Eigen::Translation3d(0.3, -0.1, 2) * Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitY());
    welder.weld(mesh.primitives, t, positions);
    for (size_t i = 0; i < positions.size(); ++i)
        EXPECT_LT((positions[i] - t * mesh.visual.positions[i]).norm(), 1e-15 * 4.0) << i;
}

TEST(VertexWelder, MovedPrimitivesWeldToTheAverageOfTheirVertices) {
    const PhysicalMesh mesh = extrudedGrid();
    const int n = int(mesh.visual.positions.size());
    const VertexWelder welder(mesh.primitives, n);
    const std::vector<ConvexPolyhedron> moved = jiggled(mesh.primitives, 5);
    const Eigen::Isometry3d t = Eigen::Translation3d(1, 2, 3) * Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitX());
    std::vector<Eigen::Vector3d> positions;
    welder.weld(moved, t, positions);

    // Reference by brute force.
    std::vector<Eigen::Vector3d> sum(n, Eigen::Vector3d::Zero());
    std::vector<int> count(n, 0);
    for (const auto& p : moved)
        for (size_t k = 0; k < p.vertices().size(); ++k)
            if (p.globalIds()[k] < n) {
                sum[p.globalIds()[k]] += p.vertices()[k];
                ++count[p.globalIds()[k]];
            }
    for (int id = 0; id < n; ++id) {
        ASSERT_GT(count[id], 0);
        EXPECT_LT((positions[id] - t * (sum[id] / count[id])).norm(), 1e-14) << id;
    }

    // By hand: interior grid vertex (1, 1) = index 6 is a corner of the quads (0,0), (1,0),
    // (0,1), (1,1), i.e. primitives 0, 1, 4, 5, where it is top vertex 2, 3, 1, 0.
    const Eigen::Vector3d byHand =
        (moved[0].vertices()[2] + moved[1].vertices()[3] + moved[4].vertices()[1] + moved[5].vertices()[0]) / 4.0;
    ASSERT_EQ(moved[0].globalIds()[2], 6);
    ASSERT_EQ(moved[5].globalIds()[0], 6);
    EXPECT_EQ(count[6], 4);
    EXPECT_LT((positions[6] - t * byHand).norm(), 1e-14);
    // The jiggle really moved it: welded differs from rest by about 1e-3, not by round-off.
    EXPECT_GT((positions[6] - t * mesh.visual.positions[6]).norm(), 1e-5);
}

TEST(VertexWelder, FlatVerticesWeldLikePolyhedra) {
    const PhysicalMesh mesh = extrudedGrid();
    const int n = int(mesh.visual.positions.size());
    const VertexWelder welder(mesh.primitives, n);
    const std::vector<ConvexPolyhedron> moved = jiggled(mesh.primitives, 8);
    std::vector<Eigen::Vector3d> flat;
    for (const auto& p : moved) flat.insert(flat.end(), p.vertices().begin(), p.vertices().end());
    const Eigen::Isometry3d t = Eigen::Translation3d(0.3, -1.0, 2.0) * Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitY());
    std::vector<Eigen::Vector3d> a, b;
    welder.weld(moved, t, a);
    welder.weld(flat, t, b);
    EXPECT_EQ(a, b);
}

TEST(VertexWelder, IdsNoPrimitiveCarriesAreLeftAlone) {
    // Two positions that no face uses: no primitive carries their ids.
    shatter::test::FaceMesh grid = shatter::test::quadGrid(2, 2, 1.0);
    const int n = int(grid.positions.size());
    grid.positions.emplace_back(5, 5, 5);
    grid.positions.emplace_back(6, 6, 6);
    const PhysicalMesh mesh = buildPhysicalMesh("grid", grid.positions, grid.faces);
    const VertexWelder welder(mesh.primitives, n + 2);
    std::vector<Eigen::Vector3d> positions(n + 2, Eigen::Vector3d(7, 7, 7));
    welder.weld(mesh.primitives, Eigen::Isometry3d::Identity(), positions);
    EXPECT_EQ(positions[n], Eigen::Vector3d(7, 7, 7));
    EXPECT_EQ(positions[n + 1], Eigen::Vector3d(7, 7, 7));
    for (int i = 0; i < n; ++i) EXPECT_EQ(positions[i], grid.positions[i]);
}

TEST(VertexWelder, OtherPrimitivesThanAtConstructionAreRejected) {
    const PhysicalMesh mesh = extrudedGrid();
    const VertexWelder welder(mesh.primitives, int(mesh.visual.positions.size()));
    std::vector<ConvexPolyhedron> fewer(mesh.primitives.begin(), mesh.primitives.end() - 1);
    std::vector<Eigen::Vector3d> positions;
    EXPECT_THROW(welder.weld(fewer, Eigen::Isometry3d::Identity(), positions), std::invalid_argument);
    std::vector<Eigen::Vector3d> flat;
    for (const auto& p : mesh.primitives) flat.insert(flat.end(), p.vertices().begin(), p.vertices().end());
    flat.pop_back();
    EXPECT_THROW(welder.weld(flat, Eigen::Isometry3d::Identity(), positions), std::invalid_argument);
}
