#pragma once
// Per-thread scratch of values, one per index, each made when first asked for in a use and
// reused by that use's later asks: the turned node boxes of a tree walk (AabbTree::pairsWith),
// the turned primitive boxes of a group pair's step (NearBoxes). A stamp per index says which
// use made its value, so a use starts in O(1), not by clearing the scratch.
#include <algorithm>
#include <cassert>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

namespace shatter::geometry {

// One scratch per thread and Value type. A use (one object) sees only values it made itself:
// an inner use of the same type on the thread (not expected: a debug build asserts) restamps
// what it makes, and the outer use then makes those values again.
template <typename Value>
class StampedScratch {
public:
    // For indices 0 .. count - 1.
    explicit StampedScratch(std::size_t count) : scratch_(perThread()) {
        assert(!scratch_.active && "one use of a StampedScratch type at a time on a thread");
#ifndef NDEBUG
        scratch_.active = true;
#endif
        if (scratch_.stamps.size() < count) {
            scratch_.values.resize(count);
            scratch_.stamps.resize(count, 0);
        }
        if (++scratch_.use == 0) { // wrapped: no stamp may look like this use's
            std::fill(scratch_.stamps.begin(), scratch_.stamps.end(), 0);
            scratch_.use = 1;
        }
        use_ = scratch_.use;
    }
    ~StampedScratch() {
#ifndef NDEBUG
        scratch_.active = false;
#endif
    }
    StampedScratch(const StampedScratch&) = delete;
    StampedScratch& operator=(const StampedScratch&) = delete;

    // Index i's value: make() if this use has not made it yet. Valid until the next ask.
    template <typename Make>
    const Value& get(std::size_t i, const Make& make) {
        std::optional<Value>& value = scratch_.values[i];
        if (scratch_.stamps[i] != use_) {
            value.emplace(Made<Make>{make}); // make()'s value built in place, not moved in
            scratch_.stamps[i] = use_;
        }
        return *value;
    }

private:
    template <typename Make>
    struct Made {
        const Make& make;
        operator Value() const { return make(); }
    };
    struct PerThread {
        std::vector<std::optional<Value>> values; // optional: Value need not be assignable
        std::vector<std::uint32_t> stamps;
        std::uint32_t use = 0;
        bool active = false; // debug builds: a use is open
    };
    static PerThread& perThread() {
        thread_local PerThread scratch;
        return scratch;
    }

    PerThread& scratch_;
    std::uint32_t use_;
};

} // namespace shatter::geometry
