#pragma once
// Disjoint sets over 0..n-1 (path halving, union by index so results do not depend on
// the order of unions beyond which sets are joined).
#include <cassert>
#include <cstddef>
#include <numeric>
#include <utility>
#include <vector>

namespace shatter::geometry {

class UnionFind {
public:
    explicit UnionFind(int n) : parent_(n) { std::iota(parent_.begin(), parent_.end(), 0); }
    // Adopts a forest built elsewhere: each item's parent (a root's is itself), never above
    // the item, as unions and path halving leave them (parent() promises it). The caller's
    // promise: asserted in debug builds, not checked in Release.
    explicit UnionFind(std::vector<int> parents) : parent_(std::move(parents)) {
        for (size_t i = 0; i < parent_.size(); ++i) assert(parent_[i] >= 0 && size_t(parent_[i]) <= i);
    }

    int find(int i) {
        while (parent_[i] != i) {
            parent_[i] = parent_[parent_[i]];
            i = parent_[i];
        }
        return i;
    }
    // Joins the sets of a and b; the smaller root index becomes the root. Returns false
    // when they already were one set.
    bool unite(int a, int b) {
        a = find(a);
        b = find(b);
        if (a == b) return false;
        if (b < a) std::swap(a, b);
        parent_[b] = a;
        return true;
    }

    // i's parent (i itself for a root). Never above i: a union hangs the larger root under
    // the smaller and path halving only moves i further up, so a scan of 0..n-1 meets each
    // parent before its children (labels components without a find per item).
    int parent(int i) const { return parent_[i]; }

private:
    std::vector<int> parent_;
};

} // namespace shatter::geometry
