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

} // namespace
} // namespace shatter::geometry
