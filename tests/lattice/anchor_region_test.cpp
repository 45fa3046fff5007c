// Anchor regions: the fixed tets of a body chosen by where their centroids lie.
#include <shatter/plugin/common/InputError.h>
#include <shatter/plugin/lattice/AnchorRegion.h>
#include <shatter/plugin/lattice/Lattice.h>
#include <shatter/plugin/lattice/TetGenerators.h>

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

namespace shatter::lattice {
namespace {

// A 1 × 1 × 1 m box of 4 × 4 × 4 cells, centred on the origin: layers of cells 0.25 m high.
TetMesh cube() { return tetBox({1.0, 1.0, 1.0}, {4, 4, 4}); }

TEST(AnchorRegion, BelowTheFirstLayerIsTheBottomLayerOfABox) {
    // The tets of the lowest cell layer (y in [-0.5, -0.25]) have their centroids below
    // -0.25, all others above: exactly a quarter of the tets, among them every tet with a face
    // on the bottom plane (what the demos anchored by before).
    const TetMesh mesh = cube();
    const std::vector<int> below = tetsInRegion(mesh, AnchorRegion::below(-0.25));
    EXPECT_EQ(below.size(), mesh.tets.size() / 4);
    for (int t : below) EXPECT_LE(centroid(mesh, mesh.tets[t]).y(), -0.25);
    for (int t : tetsWithFaceOnPlane(mesh, {0, 1, 0}, -0.5, 1e-9))
        EXPECT_TRUE(std::binary_search(below.begin(), below.end(), t)) << "tet " << t;
}

TEST(AnchorRegion, HalfSpaceNormalNeedNotBeUnitNorAlongAnAxis) {
    // n = (2, 0, 0), d = 0: the same as x <= 0 (the offset is along the normalised normal),
    // which holds exactly the left half of a mesh symmetric about x = 0.
    const TetMesh mesh = cube();
    const auto left = tetsInRegion(mesh, AnchorRegion::halfSpace({2, 0, 0}, 0.0));
    EXPECT_EQ(left.size(), mesh.tets.size() / 2);
    // A tilted plane through the origin also splits the centrally symmetric box in halves,
    // up to the tets whose centroid lies on it; none does for this irrational-ish normal.
    const auto tilted = tetsInRegion(mesh, AnchorRegion::halfSpace({1, 0.37, 0.11}, 0.0));
    EXPECT_EQ(tilted.size(), mesh.tets.size() / 2);
}

TEST(AnchorRegion, BoxHoldsTheTetsWhoseCentroidIsInside) {
    const TetMesh mesh = cube();
    // One corner cell, x, y, z in [-0.5, -0.25]: its six tets.
    const auto corner = tetsInRegion(mesh, AnchorRegion::box({-0.5, -0.5, -0.5}, {-0.25, -0.25, -0.25}));
    EXPECT_EQ(corner.size(), 6u);
    // The whole mesh, and nothing when the box lies outside it.
    EXPECT_EQ(tetsInRegion(mesh, AnchorRegion::box({-1, -1, -1}, {1, 1, 1})).size(), mesh.tets.size());
    EXPECT_TRUE(tetsInRegion(mesh, AnchorRegion::box({2, 2, 2}, {3, 3, 3})).empty());
}

TEST(AnchorRegion, AnEmptyRegionIsAnErrorNamingTheBody) {
    try {
        anchoredTets(cube(), AnchorRegion::below(-0.6), "statue");
        FAIL() << "no error";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("body 'statue': the anchor region"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("holds no tet"), std::string::npos) << e.what();
    }
}

TEST(AnchorRegion, AWorldRegionIsTestedWhereTheBodyIsPlaced) {
    // The cube placed 2 m up and turned a quarter round z (mesh x becomes world y): world
    // y <= 1.75 holds the mesh's tets with centroid x <= -0.25, the same count as the mesh's
    // bottom layer; in mesh coordinates the same region holds every tet.
    const TetMesh mesh = cube();
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.translate(Eigen::Vector3d(0, 2, 0)).rotate(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()));
    const AnchorRegion region = AnchorRegion::below(1.75).inWorld();
    const auto world = tetsInRegion(mesh, region, pose);
    EXPECT_EQ(world, tetsInRegion(mesh, AnchorRegion::halfSpace({1, 0, 0}, -0.25)));
    EXPECT_EQ(world.size(), mesh.tets.size() / 4);
    EXPECT_EQ(tetsInRegion(mesh, AnchorRegion::below(1.75), pose).size(), mesh.tets.size());
    try {
        anchoredTets(mesh, AnchorRegion::below(0.0).inWorld(), "statue", pose);
        FAIL() << "no error";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("body 'statue': the anchor region n·x <= 0 with n = (0, 1, 0) (world coordinates) holds no tet"),
                  std::string::npos)
            << e.what();
    }
}

TEST(AnchorRegion, BadRegionsAreRejected) {
    EXPECT_THROW(AnchorRegion::halfSpace({0, 0, 0}, 1.0), InputError);
    EXPECT_THROW(AnchorRegion::halfSpace({0, 1, 0}, NAN), InputError);
    EXPECT_THROW(AnchorRegion::box({1, 0, 0}, {0, 1, 1}), InputError);
    EXPECT_THROW(AnchorRegion::box({0, 0, 0}, {INFINITY, 1, 1}), InputError);
}

} // namespace
} // namespace shatter::lattice
