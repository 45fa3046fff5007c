#pragma once
// The pending nodes of a depth-first tree walk: a fixed buffer on the call's stack, and a heap
// vector only for a walk deeper than it. An edited tree is not rebalanced (AabbTree::append
// hangs what it adds under a new root), so its depth grows by one per edit: a body broken in
// place a hundred times holds a tree deeper than any median split gives.
#include <array>
#include <vector>

namespace shatter::geometry {

template <typename T, int kInline = 128>
class WalkStack {
public:
    bool empty() const { return top_ == 0; }

    void push(const T& value) {
        if (top_ < kInline)
            inline_[size_t(top_)] = value;
        else
            spilled_.push_back(value);
        ++top_;
    }

    T pop() {
        --top_;
        if (top_ < kInline) return inline_[size_t(top_)];
        const T value = spilled_.back();
        spilled_.pop_back();
        return value;
    }

private:
    std::array<T, kInline> inline_;
    std::vector<T> spilled_;
    int top_ = 0;
};

} // namespace shatter::geometry
