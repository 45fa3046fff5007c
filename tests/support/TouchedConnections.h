#pragma once
// The check a rest edited in place (fracture::RemainderEdit) must pass: its touchedConnections
// list every body connection with an end the rest loses, so that applyRemainderEdit, which
// keeps the others without looking at their ends, gives the connections of looking up both
// ends of every one.
#include <shatter/plugin/fracture/RemainderEdit.h>
#include <shatter/plugin/geometry/HoleFilling.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <utility>
#include <vector>

namespace shatter::test {

// Exact: the list is strictly ascending and in range, every connection with a removed end is
// in it, and the edited rest's connections begin with the body's between two kept primitives,
// renumbered, in their order (then the edit's own follow).
inline void expectTouchedConnectionsComplete(const geometry::PhysicalMesh& body, const fracture::RemainderEdit& edit) {
    const std::vector<int>& touched = edit.touchedConnections;
    EXPECT_EQ(std::adjacent_find(touched.begin(), touched.end(), std::greater_equal<>()), touched.end());
    std::vector<char> removed(body.primitives.size(), 0), listed(body.connections.size(), 0);
    for (int p : edit.removed) removed[size_t(p)] = 1;
    for (int c : touched) {
        ASSERT_GE(c, 0);
        ASSERT_LT(c, int(body.connections.size()));
        listed[size_t(c)] = 1;
    }
    for (size_t c = 0; c < body.connections.size(); ++c) {
        const auto [a, b] = body.connections[c];
        if (removed[size_t(a)] || removed[size_t(b)]) {
            EXPECT_TRUE(listed[c]) << "connection " << c << " (" << a << ", " << b << ")";
        }
    }
    const int before = int(body.primitives.size());
    const geometry::HoleFilling slots = geometry::fillHoles(before, edit.removed, int(edit.added.size()));
    const std::vector<int> to = slots.newIndex(before, edit.removed);
    std::vector<std::pair<int, int>> expected;
    for (const auto& [a, b] : body.connections)
        if (to[size_t(a)] >= 0 && to[size_t(b)] >= 0) expected.emplace_back(std::minmax(to[size_t(a)], to[size_t(b)]));
    geometry::PhysicalMesh rest = body;
    fracture::applyRemainderEdit(rest, edit);
    ASSERT_EQ(rest.connections.size(), expected.size() + edit.connections.size());
    EXPECT_TRUE(std::equal(expected.begin(), expected.end(), rest.connections.begin()));
}

} // namespace shatter::test
