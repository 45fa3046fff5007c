// fillHoles: the places of an edit that removes some items and adds others must number the
// result 0 .. size - 1 exactly once, move only O(removed + added) items, and a tree edited
// with them must answer like a tree built over the items in those places.
#include <shatter/plugin/geometry/AabbTree.h>
#include <shatter/plugin/geometry/HoleFilling.h>
#include "tests/support/RandomBoxes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>

using namespace shatter::geometry;
using shatter::test::randomBoxes;

namespace {

std::vector<int> randomRemoved(int count, int r, std::mt19937& rng) {
    std::vector<int> all(static_cast<size_t>(count));
    for (int i = 0; i < count; ++i) all[size_t(i)] = i;
    std::shuffle(all.begin(), all.end(), rng);
    all.resize(size_t(r));
    std::sort(all.begin(), all.end());
    return all;
}

} // namespace

TEST(HoleFilling, PlacesAreEachUsedOnceAndOnlyTheTailMoves) {
    std::mt19937 rng(3);
    // Fewer, as many and more added than removed; removals at the end, at the start, none.
    for (int trial = 0; trial < 300; ++trial) {
        const int count = 1 + int(rng() % 60);
        const int r = int(rng() % (count + 1));
        const int added = int(rng() % 40);
        std::vector<int> removed = trial % 7 == 0 ? std::vector<int>{} : randomRemoved(count, r, rng);
        if (trial % 11 == 0) { // the last ones
            removed.clear();
            for (int i = count - r; i < count; ++i) removed.push_back(i);
        }
        const int rr = int(removed.size());
        const HoleFilling slots = fillHoles(count, removed, added);
        ASSERT_EQ(slots.size, count - rr + added);
        const std::vector<int> to = slots.newIndex(count, removed);
        std::vector<int> used(static_cast<size_t>(slots.size), 0);
        for (int i = 0; i < count; ++i) {
            const bool gone = std::binary_search(removed.begin(), removed.end(), i);
            EXPECT_EQ(to[size_t(i)] < 0, gone);
            if (to[size_t(i)] >= 0) ++used[size_t(to[size_t(i)])];
            // A survivor stays unless it lies beyond the new end.
            if (!gone && i < slots.size) {
                EXPECT_EQ(to[size_t(i)], i);
            }
        }
        ASSERT_EQ(slots.addedAt.size(), size_t(added));
        for (int j = 0; j < added; ++j) {
            ++used[size_t(slots.addedAt[size_t(j)])];
            if (j < rr) {
                EXPECT_EQ(slots.addedAt[size_t(j)], removed[size_t(j)]);
            }
        }
        for (int u : used) ASSERT_EQ(u, 1);
        EXPECT_LE(slots.moves.size(), removed.size());
        for (const auto& [from, hole] : slots.moves) {
            EXPECT_GE(from, slots.size);
            EXPECT_LT(hole, slots.size);
        }
        EXPECT_EQ(fillHoles(count, removed, added).moves, slots.moves); // same edit, same places
    }
}

TEST(HoleFilling, ATreeEditedInThosePlacesAnswersLikeABuild) {
    std::mt19937 rng(5);
    for (const auto& [count, r, added] : {std::tuple{300, 40, 25}, {300, 25, 40}, {300, 300, 10}, {200, 0, 30}}) {
        const auto boxes = randomBoxes(count, 11), extra = randomBoxes(added, 13);
        const std::vector<int> removed = randomRemoved(count, r, rng);
        const HoleFilling slots = fillHoles(count, removed, added);
        const std::vector<int> to = slots.newIndex(count, removed);
        std::vector<Aabb> placed(static_cast<size_t>(slots.size));
        for (int i = 0; i < count; ++i)
            if (to[size_t(i)] >= 0) placed[size_t(to[size_t(i)])] = boxes[size_t(i)];
        for (int j = 0; j < added; ++j) placed[size_t(slots.addedAt[size_t(j)])] = extra[size_t(j)];
        AabbTree edited(boxes);
        edited.fillHoles(removed, slots, extra);
        EXPECT_EQ(edited.itemCount(), slots.size);
        const AabbTree built(placed);
        size_t hits = 0;
        for (const auto& small : randomBoxes(50, 19)) {
            std::set<int> a, b;
            edited.query(small.inflated(1.0), [&](int i) { EXPECT_TRUE(a.insert(i).second) << "item reported twice"; });
            built.query(small.inflated(1.0), [&](int i) { b.insert(i); });
            EXPECT_EQ(a, b);
            hits += a.size();
        }
        EXPECT_GT(hits, size_t(slots.size) / 10); // the queries really find items
        Aabb all;
        for (const auto& box : placed) all.extend(box);
        EXPECT_EQ(edited.bounds().min, all.min); // GroupShape::fillPrimitives takes its box from here
        EXPECT_EQ(edited.bounds().max, all.max);
    }
}
