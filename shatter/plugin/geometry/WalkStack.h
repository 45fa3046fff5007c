#pragma once
// The pending nodes of a depth-first tree walk: a fixed buffer on the call's stack, and a heap
// vector only for a walk deeper than it. An edited tree is not rebalanced (AabbTree::append
// hangs what it adds under a new root), so its depth grows by one per edit: a body broken in
// place a hundred times holds a tree deeper than any median split gives.
#include <array>
#include <memory>
#include <type_traits>
#include <vector>

namespace shatter::geometry {

// The buffer is left uninitialised (entries are written before they are read): a walk over
// a few nodes no longer value-initialises 128 entries (a std::pair's zeroes) first.
template <typename T, int kInline = 128>
class WalkStack {
    static_assert(std::is_trivially_destructible_v<T>); // a slot is overwritten without a destructor call

public:
    bool empty() const { return top_ == 0; }

    void push(const T& value) {
        if (top_ < kInline)
            std::construct_at(&inline_[size_t(top_)].value, value);
        else
            spilled_.push_back(value);
        ++top_;
    }

    T pop() {
        --top_;
        if (top_ < kInline) return inline_[size_t(top_)].value;
        const T value = spilled_.back();
        spilled_.pop_back();
        return value;
    }

private:
    union Slot { // no constructor of T runs: the slot holds nothing until push writes it
        Slot() {}
        T value;
    };
    std::array<Slot, kInline> inline_;
    std::vector<T> spilled_;
    int top_ = 0;
};

} // namespace shatter::geometry
