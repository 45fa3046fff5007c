#include <shatter/plugin/geometry/UnionFind.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <vector>

namespace shatter::geometry {
namespace {

// A parent never comes after its child (what a one-pass labelling of the sets relies on),
// whatever the order of the unions and of the finds that halve the paths; each root is its
// set's smallest item.
TEST(UnionFind, AParentNeverComesAfterItsChildAndRootsAreTheSmallest) {
    const int n = 200;
    UnionFind sets(n);
    std::vector<int> smallest(n); // by brute force: the smallest item joined to each
    std::vector<int> label(n);
    for (int i = 0; i < n; ++i) label[i] = i;
    std::uint32_t state = 12345;
    auto next = [&] { return int((state = state * 1664525u + 1013904223u) >> 8) % n; };
    for (int k = 0; k < 150; ++k) {
        const int a = next(), b = next();
        sets.unite(b, a);
        const int from = label[a], to = label[b];
        for (int& l : label)
            if (l == from) l = to;
        if (k % 7 == 0) sets.find(next());
        for (int i = 0; i < n; ++i) EXPECT_LE(sets.parent(i), i);
    }
    for (int i = 0; i < n; ++i) {
        smallest[i] = i;
        for (int j = 0; j < n; ++j)
            if (label[j] == label[i]) smallest[i] = std::min(smallest[i], j);
        EXPECT_EQ(sets.find(i), smallest[i]);
        EXPECT_EQ(sets.parent(sets.find(i)), sets.find(i));
    }
}

// A forest adopted from another union-find's parents (as the fracture's islands adopt the one
// it builds over primitives) holds the same sets and keeps joining them the same way.
TEST(UnionFind, AnAdoptedForestHoldsTheSameSets) {
    const int n = 100;
    UnionFind built(n);
    std::uint32_t state = 777;
    auto next = [&] { return int((state = state * 1664525u + 1013904223u) >> 8) % n; };
    for (int k = 0; k < 60; ++k) built.unite(next(), next());
    std::vector<int> parents(n);
    for (int i = 0; i < n; ++i) parents[size_t(i)] = built.parent(i);
    UnionFind adopted(parents);
    for (int i = 0; i < n; ++i) {
        EXPECT_EQ(adopted.parent(i), parents[size_t(i)]);
        EXPECT_EQ(adopted.find(i), built.find(i));
    }
    for (int k = 0; k < 20; ++k) {
        const int a = next(), b = next();
        EXPECT_EQ(adopted.unite(a, b), built.unite(a, b));
    }
    for (int i = 0; i < n; ++i) EXPECT_EQ(adopted.find(i), built.find(i));
}

} // namespace
} // namespace shatter::geometry
