// The bounding-volume tree must report exactly the overlapping pairs a brute force finds.
#include <shatter/plugin/geometry/AabbTree.h>
#include "tests/support/RandomBoxes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <stdexcept>
#include <set>
#include <vector>

using namespace shatter::geometry;
using shatter::test::randomBoxes;

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

// The pairs come in the recursive walk's order (a soft body's self contacts are solved in
// it): a node against itself is its left child against itself, the right against itself, then
// left against right; of two nodes the one with the longer extent sum descends first.
TEST(AabbTree, SelfPairsComeInTheRecursiveWalksOrder) {
    // Four boxes in a row: the tree is {0, 1} beside {2, 3}, so 1-2 (between the halves) comes last.
    std::vector<Aabb> row(4);
    for (int i = 0; i < 4; ++i) row[size_t(i)] = {Eigen::Vector3d(i, 0, 0), Eigen::Vector3d(i + 1.1, 1, 1)};
    std::vector<std::pair<int, int>> pairs;
    AabbTree(row).selfPairs([&](int a, int b) { pairs.emplace_back(a, b); });
    EXPECT_EQ(pairs, (std::vector<std::pair<int, int>>{{0, 1}, {2, 3}, {1, 2}}));

    // 300 boxes from an integer generator (the same doubles everywhere): the order the
    // recursive walk of main 1135ba3 gave, as a hash of the pair sequence.
    std::vector<Aabb> boxes(300);
    unsigned s = 12345;
    auto next = [&] {
        s = s * 1103515245u + 12345u;
        return double((s >> 16) & 1023) / 1024.0;
    };
    // One draw per statement: the order of a call's arguments is the compiler's (GCC took them
    // last to first, clang first to last), so the draws are sequenced as GCC made them.
    for (auto& box : boxes) {
        box.min.z() = 2.0 * next();
        box.min.y() = 8.0 * next();
        box.min.x() = 8.0 * next();
        Eigen::Vector3d size;
        size.z() = 0.1 + 0.5 * next();
        size.y() = 0.2 + next();
        size.x() = 0.2 + next();
        box.max = box.min + size;
    }
    unsigned long long hash = 1469598103934665603ull; // FNV-1a over the items in order
    int count = 0;
    AabbTree(boxes).selfPairs([&](int a, int b) {
        hash = (hash ^ unsigned(a)) * 1099511628211ull;
        hash = (hash ^ unsigned(b)) * 1099511628211ull;
        ++count;
    });
    EXPECT_EQ(count, 377);
    EXPECT_EQ(hash, 16242250527469226797ull);
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

// The branch and bound finds the largest value over all items (here a box's farthest corner
// from a point, whose bound for a node is the same function of its box), whatever the point,
// and the larger child first makes the floor rise early: one or two of 2,000 items are read
// (40 to 67 with the smaller child first).
TEST(AabbTree, LargestFirstFindsTheMaximumReadingFewItems) {
    const auto boxes = randomBoxes(2000, 13);
    AabbTree tree(boxes);
    auto farthest = [](const Aabb& box, const Eigen::Vector3d& c) {
        return (box.min - c).cwiseAbs().cwiseMax((box.max - c).cwiseAbs()).squaredNorm();
    };
    for (const Eigen::Vector3d& c : {Eigen::Vector3d(5, 5, 5), Eigen::Vector3d(1, 9, 2), Eigen::Vector3d(-20, 4, 30)}) {
        double expected = 0.0;
        for (const Aabb& box : boxes) expected = std::max(expected, farthest(box, c));
        double found = 0.0;
        int read = 0;
        tree.searchLargestFirst([&](const Aabb& box) { return farthest(box, c); }, [&] { return found; },
                                [&](int item) {
                                    ++read;
                                    found = std::max(found, farthest(boxes[size_t(item)], c));
                                });
        EXPECT_EQ(found, expected);
        EXPECT_LE(read, 8) << "the larger child was not taken first";
    }
    // An empty tree visits nothing.
    AabbTree().searchLargestFirst([](const Aabb&) { return 1.0; }, [] { return 0.0; },
                                  [](int) { ADD_FAILURE() << "an empty tree has no items"; });
}

// A tree grown node by node is the tree refitted to the grown item boxes, bit for bit: every
// box of the walk, in order (GroupShape's contact tree is made this way). Boxes at signed
// zeros and below the origin included, and a growth of zero.
TEST(AabbTree, InflatingIsRefittingToTheGrownBoxes) {
    auto boxes = randomBoxes(500, 17);
    for (size_t i = 0; i < boxes.size(); i += 7) boxes[i].min.x() = (i % 2 ? -0.0 : 0.0);
    for (size_t i = 3; i < boxes.size(); i += 11) boxes[i].min -= Eigen::Vector3d(12, 12, 12);
    auto walk = [](const AabbTree& tree) {
        std::vector<double> seen;
        tree.search([&](const Aabb& b) {
            seen.insert(seen.end(), {b.min.x(), b.min.y(), b.min.z(), b.max.x(), b.max.y(), b.max.z()});
            return true;
        }, [](int) {});
        return seen;
    };
    for (const double r : {0.0, 0.01, 0.3}) {
        const AabbTree built(boxes);
        std::vector<Aabb> grown;
        for (const Aabb& b : boxes) grown.push_back(b.inflated(r));
        AabbTree refitted(built, 0), inflated(built, 0);
        refitted.refit(grown);
        inflated.inflate(r);
        const auto a = walk(refitted), b = walk(inflated);
        ASSERT_EQ(a.size(), b.size());
        EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(double)), 0) << "growth " << r;
        if (r > 0) {
            EXPECT_NE(walk(built), b); // it did grow
        }
    }
    AabbTree tree(boxes);
    EXPECT_THROW(tree.inflate(-0.01), std::invalid_argument);
    EXPECT_THROW(tree.inflate(std::nan("")), std::invalid_argument);
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

TEST(AabbTree, PairsWithADepthVisitTheDeepPairsInTheUnprunedOrder) {
    // Every pair whose leaf boxes overlap by the depth is visited, and the visits are some of
    // the unpruned walk's, in its order (the descent does not depend on the depth).
    const auto a = randomBoxes(200, 3), b = randomBoxes(150, 5);
    const Eigen::Isometry3d t = Eigen::Translation3d(1, 0.5, -0.5) * Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ());
    const Eigen::Vector3d depth(0.2, 0.05, 0.1);
    std::vector<std::pair<int, int>> all, deep;
    AabbTree(a).pairsWith(AabbTree(b), t, [&](int i, int j) { all.push_back({i, j}); });
    AabbTree(a).pairsWith(AabbTree(b), t, [&](int i, int j) { deep.push_back({i, j}); }, depth);
    std::vector<std::pair<int, int>> kept; // the unpruned visits whose leaf boxes overlap that deep
    for (const auto& [i, j] : all) {
        const Aabb tb = transformedAabb(b[size_t(j)], t);
        const Aabb& ta = a[size_t(i)];
        if (((tb.max - ta.min).array() >= depth.array()).all() && ((ta.max - tb.min).array() >= depth.array()).all())
            kept.push_back({i, j});
    }
    EXPECT_LT(deep.size(), all.size());
    EXPECT_GT(kept.size(), 10u);
    EXPECT_EQ(deep, kept);
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

TEST(AabbTree, RemovingAndAppendingItemsAnswersLikeABuildOverTheResult) {
    // Every third box leaves, 40 new ones come: the edited tree reports, for many query
    // boxes, exactly the items (in the new numbering) a tree built over the result reports.
    const auto boxes = randomBoxes(300, 13), extra = randomBoxes(40, 17);
    std::vector<int> newIndex(boxes.size());
    std::vector<Aabb> result;
    for (size_t i = 0; i < boxes.size(); ++i) {
        newIndex[i] = i % 3 == 0 ? -1 : int(result.size());
        if (newIndex[i] >= 0) result.push_back(boxes[i]);
    }
    result.insert(result.end(), extra.begin(), extra.end());
    AabbTree edited(boxes);
    edited.removeAndAppend(newIndex, extra);
    EXPECT_EQ(edited.itemCount(), int(result.size()));
    const AabbTree built(result);
    const auto queries = randomBoxes(50, 19);
    size_t hits = 0;
    for (const auto& small : queries) {
        const Aabb q = small.inflated(1.0);
        std::set<int> a, b;
        edited.query(q, [&](int i) { EXPECT_TRUE(a.insert(i).second) << "item reported twice"; });
        built.query(q, [&](int i) { b.insert(i); });
        EXPECT_EQ(a, b);
        hits += a.size();
    }
    EXPECT_GT(hits, 200u); // the queries really find items
    // Everything removed: only the new items are left.
    AabbTree gone(boxes);
    gone.removeAndAppend(std::vector<int>(boxes.size(), -1), extra);
    EXPECT_EQ(gone.itemCount(), 40);
    std::set<int> all;
    gone.query(Aabb{{-1, -1, -1}, {12, 12, 12}}, [&](int i) { all.insert(i); });
    EXPECT_EQ(all.size(), 40u);
    EXPECT_EQ(*all.rbegin(), 39);
}

TEST(AabbTree, RoomForMoreNodesChangesNoTreeAndNoEdit) {
    // Room for appended nodes (GroupShape's trees, so a fracture's edit of the rest does not
    // move them) must leave the tree as it is: queries visit the same items in the same order
    // (the same shape), before and after an edit, for a tree built with room and for a copy
    // given room.
    const auto boxes = randomBoxes(300, 29), extra = randomBoxes(60, 31);
    std::vector<int> newIndex(boxes.size());
    int kept = 0;
    for (size_t i = 0; i < boxes.size(); ++i) newIndex[i] = i % 5 == 0 ? -1 : kept++;
    AabbTree plain(boxes), roomy(boxes, 500);
    AabbTree copied(plain, 500);
    const auto visits = [](const AabbTree& tree) {
        std::vector<int> order;
        for (const auto& small : randomBoxes(30, 37)) tree.query(small.inflated(1.0), [&](int i) { order.push_back(i); });
        return order;
    };
    const std::vector<int> before = visits(plain);
    EXPECT_GT(before.size(), 100u); // the queries really find items
    EXPECT_EQ(visits(roomy), before);
    EXPECT_EQ(visits(copied), before);
    plain.removeAndAppend(newIndex, extra);
    roomy.removeAndAppend(newIndex, extra);
    copied.removeAndAppend(newIndex, extra);
    const std::vector<int> after = visits(plain);
    EXPECT_NE(after, before);
    EXPECT_EQ(visits(roomy), after);
    EXPECT_EQ(visits(copied), after);
    EXPECT_EQ(copied.itemCount(), plain.itemCount());
}

TEST(AabbTree, ManyEditsInARowAnswerLikeABuildAndRefitAfterwards) {
    // A body broken again and again: each edit leaves unreachable nodes behind in the tree
    // (and now and then drops them); queries, self pairs and a refit must not see them.
    std::vector<Aabb> current = randomBoxes(200, 23);
    AabbTree edited(current);
    for (int round = 0; round < 12; ++round) {
        std::vector<int> newIndex(current.size());
        std::vector<Aabb> result;
        for (size_t i = 0; i < current.size(); ++i) {
            newIndex[i] = (i + size_t(round)) % 4 == 0 ? -1 : int(result.size());
            if (newIndex[i] >= 0) result.push_back(current[i]);
        }
        const auto extra = randomBoxes(round % 3 == 0 ? 0 : 15, 100 + round);
        result.insert(result.end(), extra.begin(), extra.end());
        edited.removeAndAppend(newIndex, extra);
        current = result;
        ASSERT_EQ(edited.itemCount(), int(current.size()));
        const AabbTree built(current);
        for (const auto& small : randomBoxes(20, 200 + round)) {
            const Aabb q = small.inflated(1.0);
            std::set<int> a, b;
            edited.query(q, [&](int i) { EXPECT_TRUE(a.insert(i).second) << "item reported twice"; });
            built.query(q, [&](int i) { b.insert(i); });
            EXPECT_EQ(a, b) << "round " << round;
        }
        std::set<std::pair<int, int>> pa, pb;
        edited.selfPairs([&](int i, int j) { pa.insert({i, j}); });
        built.selfPairs([&](int i, int j) { pb.insert({i, j}); });
        EXPECT_EQ(pa, pb) << "round " << round;
    }
    // The boxes move: the refit tree answers like a build over the moved boxes.
    for (auto& box : current) box = Aabb{box.min + Eigen::Vector3d(0.5, 0, 0), box.max + Eigen::Vector3d(0.5, 0, 0)};
    edited.refit(current);
    const AabbTree built(current);
    for (const auto& small : randomBoxes(20, 300)) {
        std::set<int> a, b;
        edited.query(small.inflated(1.0), [&](int i) { a.insert(i); });
        built.query(small.inflated(1.0), [&](int i) { b.insert(i); });
        EXPECT_EQ(a, b);
    }
}

TEST(AabbTree, FillingHolesGivesTheTreeOfRemoveAndAppendAndAnswersLikeABuild) {
    // fillHoles edits a tree from the removed leaves up only (parent links, leaf per item).
    // Without appended items it must give removeAndAppend's tree for the same numbering: the
    // same items visited in the same order. With them, a tree that answers like a build. Every
    // third round edits with removeAndAppend instead, so the links it keeps are used next.
    // 1,000 items: ~100 removals a round, enough for fillHoles' farthest hints (48 on) to run.
    std::vector<Aabb> current = randomBoxes(1000, 41);
    AabbTree edited(current);
    std::mt19937 rng(43);
    const auto visits = [](const AabbTree& tree, unsigned seed) {
        std::vector<int> order;
        for (const auto& small : randomBoxes(30, seed)) tree.query(small.inflated(1.0), [&](int i) { order.push_back(i); });
        return order;
    };
    for (int round = 0; round < 15; ++round) {
        const int count = int(current.size());
        std::vector<int> removed;
        for (int i = 0; i < count; ++i)
            if (std::uniform_int_distribution<int>(0, 9)(rng) == 0) removed.push_back(i);
        if (round == 14) removed.resize(0); // nothing removed
        const auto extra = randomBoxes(round % 2 == 0 ? 0 : 20, 500 + unsigned(round));
        const HoleFilling slots = fillHoles(count, removed, int(extra.size()));
        const std::vector<int> to = slots.newIndex(count, removed);
        std::vector<Aabb> placed(size_t(slots.size));
        for (int i = 0; i < count; ++i)
            if (to[size_t(i)] >= 0) placed[size_t(to[size_t(i)])] = current[size_t(i)];
        for (size_t j = 0; j < extra.size(); ++j) placed[size_t(slots.addedAt[j])] = extra[j];

        const HoleFilling bareSlots = fillHoles(count, removed, 0);
        AabbTree reference(edited, 0);
        reference.removeAndAppend(bareSlots.newIndex(count, removed), {});
        AabbTree bare(edited, 0);
        bare.fillHoles(removed, bareSlots, {});
        EXPECT_EQ(visits(bare, 600 + unsigned(round)), visits(reference, 600 + unsigned(round))) << "round " << round;

        if (round % 3 == 2) {
            // removeAndAppend numbers the appended items after the kept ones.
            const std::vector<int> keptTo = bareSlots.newIndex(count, removed);
            std::vector<Aabb> result(size_t(count - int(removed.size())));
            for (int i = 0; i < count; ++i)
                if (keptTo[size_t(i)] >= 0) result[size_t(keptTo[size_t(i)])] = current[size_t(i)];
            result.insert(result.end(), extra.begin(), extra.end());
            edited.removeAndAppend(keptTo, extra);
            current = result;
        } else {
            edited.fillHoles(removed, slots, extra);
            current = placed;
        }
        ASSERT_EQ(edited.itemCount(), int(current.size()));
        const AabbTree built(current);
        for (const auto& small : randomBoxes(20, 700 + unsigned(round))) {
            std::set<int> a, b;
            edited.query(small.inflated(1.0), [&](int i) { EXPECT_TRUE(a.insert(i).second) << "item reported twice"; });
            built.query(small.inflated(1.0), [&](int i) { b.insert(i); });
            EXPECT_EQ(a, b) << "round " << round;
        }
        std::set<std::pair<int, int>> pa, pb;
        edited.selfPairs([&](int i, int j) { pa.insert({i, j}); });
        built.selfPairs([&](int i, int j) { pb.insert({i, j}); });
        EXPECT_EQ(pa, pb) << "round " << round;
        EXPECT_EQ(edited.bounds().min, built.bounds().min);
        EXPECT_EQ(edited.bounds().max, built.bounds().max);
    }
    // The boxes move: the refit tree answers like a build over the moved boxes.
    for (auto& box : current) box = Aabb{box.min + Eigen::Vector3d(0.5, 0, 0), box.max + Eigen::Vector3d(0.5, 0, 0)};
    edited.refit(current);
    const AabbTree built(current);
    for (const auto& small : randomBoxes(20, 800)) {
        std::set<int> a, b;
        edited.query(small.inflated(1.0), [&](int i) { a.insert(i); });
        built.query(small.inflated(1.0), [&](int i) { b.insert(i); });
        EXPECT_EQ(a, b);
    }
    // Everything removed, three items added: only those are left.
    std::vector<int> all(current.size());
    for (size_t i = 0; i < all.size(); ++i) all[i] = int(i);
    const auto three = randomBoxes(3, 900);
    edited.fillHoles(all, fillHoles(int(all.size()), all, 3), three);
    std::set<int> left;
    edited.query(Aabb{{-1, -1, -1}, {12, 12, 12}}, [&](int i) { left.insert(i); });
    EXPECT_EQ(left, (std::set<int>{0, 1, 2}));
}

TEST(AabbTree, ATreeEditedAHundredAndFiftyTimesIsWalkedWhole) {
    // Each edit that adds items hangs them under a new root, so the tree grows a level per edit
    // (a body broken in place again and again): deeper than the walks' fixed buffers. Every walk
    // must still find what a build over the same boxes finds.
    std::vector<Aabb> current = randomBoxes(400, 71);
    AabbTree edited(current);
    for (int edit = 0; edit < 150; ++edit) {
        const int count = int(current.size());
        const std::vector<int> removed = {edit % count, (7 * edit + 3) % count};
        const std::vector<int> ordered = {std::min(removed[0], removed[1]), std::max(removed[0], removed[1])};
        const std::vector<int> gone = ordered[0] == ordered[1] ? std::vector<int>{ordered[0]} : ordered;
        const auto extra = randomBoxes(3, 900 + unsigned(edit));
        const HoleFilling slots = fillHoles(count, gone, int(extra.size()));
        const std::vector<int> to = slots.newIndex(count, gone);
        std::vector<Aabb> placed(size_t(slots.size));
        for (int i = 0; i < count; ++i)
            if (to[size_t(i)] >= 0) placed[size_t(to[size_t(i)])] = current[size_t(i)];
        for (size_t j = 0; j < extra.size(); ++j) placed[size_t(slots.addedAt[j])] = extra[j];
        edited.fillHoles(gone, slots, extra);
        current = placed;
    }
    const AabbTree built(current);
    const Aabb everything{{-1, -1, -1}, {12, 12, 12}};
    std::set<int> found, expected;
    edited.query(everything, [&](int i) { found.insert(i); });
    built.query(everything, [&](int i) { expected.insert(i); });
    EXPECT_EQ(found, expected);
    EXPECT_EQ(int(found.size()), int(current.size()));
    std::set<std::pair<int, int>> pairs, builtPairs;
    edited.pairsWith(edited, Eigen::Isometry3d::Identity(), [&](int a, int b) { pairs.insert({a, b}); });
    built.pairsWith(built, Eigen::Isometry3d::Identity(), [&](int a, int b) { builtPairs.insert({a, b}); });
    EXPECT_EQ(pairs, builtPairs);
}

// The build splits at the median centre along the axis where the centres spread most, ties
// by item index: items strung along y (shuffled, two with the same centre but different sizes)
// come out, depth first, in the order of their centres' y, the tie in index order.
TEST(AabbTree, BuildOrdersLeavesByCentreAlongTheWidestAxisThenByIndex) {
    const double centreY[] = {5.0, 1.0, 3.0, 7.0, 0.0, 3.0, 6.0, 2.0, 4.0};
    std::vector<Aabb> boxes;
    for (size_t i = 0; i < std::size(centreY); ++i) {
        const double half = 0.125 * double(i + 1); // sizes differ (exact binary sums); the centres decide
        boxes.push_back({Eigen::Vector3d(-half, centreY[i] - half, 0.0), Eigen::Vector3d(half, centreY[i] + half, 0.5)});
    }
    const AabbTree tree(boxes);
    std::vector<int> leaves;
    tree.search([](const Aabb&) { return true; }, [&](int item) { leaves.push_back(item); });
    EXPECT_EQ(leaves, (std::vector<int>{4, 1, 7, 2, 5, 8, 0, 6, 3}));
}
