// The bounding-volume tree must report exactly the overlapping pairs a brute force finds.
#include <shatter/plugin/geometry/AabbTree.h>

#include <gtest/gtest.h>

#include <random>
#include <set>

using namespace shatter::geometry;

namespace {

std::vector<Aabb> randomBoxes(int n, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> pos(0.0, 10.0), size(0.05, 1.0);
    std::vector<Aabb> boxes(n);
    for (auto& b : boxes) {
        b.min = Eigen::Vector3d(pos(rng), pos(rng), pos(rng));
        b.max = b.min + Eigen::Vector3d(size(rng), size(rng), size(rng));
    }
    return boxes;
}

} // namespace

TEST(AabbTree, SelfPairsMatchBruteForce) {
    const auto boxes = randomBoxes(400, 7);
    std::set<std::pair<int, int>> expected, found;
    for (int i = 0; i < 400; ++i)
        for (int j = i + 1; j < 400; ++j)
            if (boxes[i].overlaps(boxes[j])) expected.insert({i, j});
    AabbTree tree(boxes);
    tree.selfPairs([&](int a, int b) { EXPECT_TRUE(found.insert({a, b}).second) << "pair reported twice"; });
    EXPECT_EQ(found, expected);
    EXPECT_GT(expected.size(), 50u); // the layout really has overlaps to find
}

TEST(AabbTree, QueryMatchesBruteForce) {
    const auto boxes = randomBoxes(300, 11);
    AabbTree tree(boxes);
    const Aabb q{{2, 2, 2}, {5, 4, 6}};
    std::set<int> expected, found;
    for (int i = 0; i < 300; ++i)
        if (boxes[i].overlaps(q)) expected.insert(i);
    tree.query(q, [&](int i) { found.insert(i); });
    EXPECT_EQ(found, expected);
}

TEST(AabbTree, PairsWithTransformedTreeAreConservative) {
    const auto a = randomBoxes(200, 3), b = randomBoxes(150, 5);
    const Eigen::Isometry3d t = Eigen::Translation3d(1, 0.5, -0.5) * Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ());
    std::set<std::pair<int, int>> exact, found;
    for (int i = 0; i < 200; ++i)
        for (int j = 0; j < 150; ++j)
            if (a[i].overlaps(transformedAabb(b[j], t))) exact.insert({i, j});
    AabbTree(a).pairsWith(AabbTree(b), t, [&](int i, int j) { found.insert({i, j}); });
    for (const auto& p : exact) EXPECT_TRUE(found.count(p)) << p.first << "," << p.second;
}

TEST(AabbTree, RefitFollowsMovedBoxes) {
    auto boxes = randomBoxes(100, 9);
    AabbTree tree(boxes);
    for (auto& b : boxes) {
        b.min.x() += 100.0;
        b.max.x() += 100.0;
    }
    tree.refit(boxes);
    EXPECT_GE(tree.bounds().min.x(), 100.0);
    int hits = 0;
    tree.query(boxes[42], [&](int i) { hits += (i == 42); });
    EXPECT_EQ(hits, 1);
}

TEST(AabbTree, QueryBelowPlaneFindsBoxesUnderIt) {
    const auto boxes = randomBoxes(200, 13);
    AabbTree tree(boxes);
    std::set<int> expected, found;
    for (int i = 0; i < 200; ++i)
        if (boxes[i].min.z() <= 3.0) expected.insert(i);
    tree.queryBelowPlane(Eigen::Vector3d::UnitZ(), 3.0, [&](int i) { found.insert(i); });
    EXPECT_EQ(found, expected);
}
