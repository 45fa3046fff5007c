// Sliver tets: the quality measure, and binding each sliver to its best neighbour so that it
// never breaks off alone (issue 19), on hand-made tets and on the shipped TetGen mesh of Spot.
#include <shatter/plugin/geometry/UnionFind.h>
#include <shatter/plugin/geometry/ObjFile.h>
#include <shatter/plugin/lattice/Slivers.h>
#include <shatter/plugin/lattice/TetGenProgram.h>
#include <shatter/plugin/lattice/TetGenReader.h>
#include <shatter/plugin/lattice/TetGenerators.h>

#include <gtest/gtest.h>

#include <cmath>

namespace shatter::lattice {
namespace {

TEST(Slivers, QualityIsOneForARegularTetAndScaleFree) {
    const TetMesh regular = makeTetMesh("regular", {{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}}, {{0, 2, 1, 3}});
    const Tet t = regular.tets[0];
    EXPECT_NEAR(tetQuality(regular, t), 1.0, 1e-12);
    TetMesh big = regular;
    for (auto& n : big.nodes) n *= 1000.0;
    EXPECT_NEAR(tetQuality(big, t), 1.0, 1e-12);
    // A sliver: a square's four corners lifted alternately by h out of its plane. Edges about
    // 1 (diagonals √2), volume 2h/3 for small h: quality 6√2·(2h/3)/(√2)³ = 2h.
    const double h = 0.002;
    const TetMesh flat = makeTetMesh("flat", {{0, 0, h}, {1, 0, -h}, {1, 1, h}, {0, 1, -h}}, {{0, 2, 1, 3}});
    const double q = tetQuality(flat, flat.tets[0]);
    EXPECT_NEAR(q, 2 * h, 1e-4);
    EXPECT_EQ(sliverTets(flat, 0.01), std::vector<int>{0});
    EXPECT_TRUE(sliverTets(flat, q).empty()); // strictly below
}

// Groups of tets joined by the bound links, as the root of each tet.
std::vector<int> boundGroups(const Lattice& l, const std::vector<int>& bound) {
    geometry::UnionFind groups(l.particleCount());
    for (int k : bound) groups.unite(l.links()[k].a, l.links()[k].b);
    std::vector<int> root(l.particleCount());
    for (int t = 0; t < l.particleCount(); ++t) root[t] = groups.find(t);
    return root;
}

TEST(Slivers, EverySliverOfSpotIsBoundIntoAGroupWithASoundTet) {
    // The shipped TetGen -p mesh (demos/assets/README.md): 58 of its 2,281 tets are slivers.
    const TetMesh mesh = readTetGen(std::string(SHATTER_SOURCE_DIR) + "/demos/assets/spot_tets.ele");
    Lattice lattice(mesh, MaterialSettings{});
    const std::vector<int> slivers = sliverTets(mesh, kSliverQuality);
    EXPECT_EQ(slivers.size(), 58u);
    const SliverBinding b = bindSlivers(lattice, kSliverQuality);
    EXPECT_EQ(b.slivers, 58);
    // At least one link per sliver (two slivers may share one), at most one more per group of
    // slivers bound only to each other.
    EXPECT_GE(b.links.size(), 29u);
    EXPECT_LE(b.links.size(), 2 * slivers.size());
    for (int k : b.links) EXPECT_TRUE(std::isinf(lattice.links()[k].strength)) << "link " << k;
    const std::vector<int> group = boundGroups(lattice, b.links);
    std::vector<char> sound(mesh.tets.size(), 0), isSliver(mesh.tets.size(), 0);
    for (int t : slivers) isSliver[t] = 1;
    for (int t = 0; t < int(mesh.tets.size()); ++t)
        if (!isSliver[t]) sound[group[t]] = 1;
    for (int t : slivers) EXPECT_TRUE(sound[group[t]]) << "sliver " << t << " is bound only to slivers, or to none";
    // Unbound links keep their strength (area × material strength).
    int finite = 0;
    for (const Link& l : lattice.links()) finite += std::isfinite(l.strength);
    EXPECT_EQ(finite, lattice.linkCount() - int(b.links.size()));
}

TEST(Slivers, ASoundMeshAndAZeroThresholdBindNothing) {
    Lattice box(tetBox({1, 1, 1}, {3, 3, 3}), MaterialSettings{});
    EXPECT_EQ(bindSlivers(box, kSliverQuality).slivers, 0);
    Lattice spot(readTetGen(std::string(SHATTER_SOURCE_DIR) + "/demos/assets/spot_tets.ele"), MaterialSettings{});
    const SliverBinding none = bindSlivers(spot, 0.0);
    EXPECT_EQ(none.slivers, 0);
    EXPECT_TRUE(none.links.empty());
}

// What a user with Debian's tetgen gets from the full Spot surface (5,856 triangles) with -p
// alone: the mesh of 10,274 tets, 1,599 of them slivers. Bound, none is left alone.
// Only where the external program is installed (it is not a dependency).
TEST(Slivers, TetGenWithoutAQualityBoundMakesSliversThatAllGetBound) {
    if (!tetgenAvailable()) GTEST_SKIP() << "tetgen is not installed";
    const geometry::ObjFile obj = geometry::loadObj(std::string(SHATTER_SOURCE_DIR) + "/demos/assets/spot.obj");
    std::vector<std::vector<int>> faces;
    for (const auto& object : obj.objects)
        for (const auto& f : object.faces) faces.push_back(f.vertices);
    TetGenProgramOptions o;
    o.radiusEdgeRatio = 0; // -p alone
    Lattice lattice(tetrahedralize("spot", obj.positions, faces, o), MaterialSettings{});
    EXPECT_EQ(lattice.particleCount(), 10274);
    const SliverBinding b = bindSlivers(lattice, kSliverQuality);
    EXPECT_EQ(b.slivers, 1599);
    const std::vector<int> group = boundGroups(lattice, b.links);
    std::vector<char> sound(lattice.particleCount(), 0);
    const std::vector<int> slivers = sliverTets(lattice.mesh(), kSliverQuality);
    std::vector<char> isSliver(lattice.particleCount(), 0);
    for (int t : slivers) isSliver[t] = 1;
    for (int t = 0; t < lattice.particleCount(); ++t)
        if (!isSliver[t]) sound[group[t]] = 1;
    for (int t : slivers) EXPECT_TRUE(sound[group[t]]) << "sliver " << t;
}

} // namespace
} // namespace shatter::lattice
