#pragma once
// Removing some items of an array and adding others without closing the array up in order:
// the added items take the holes, and holes left over take the last survivors. A fracture
// takes a few hundred primitives out of a body of tens of thousands and adds a few hundred
// pieces; closing up in order moved every survivor after the first hole, twice (the body's
// mesh and its group shape), where this moves O(removed + added) items.
#include <utility>
#include <vector>

namespace shatter::geometry {

struct HoleFilling {
    int size = 0;                           // items after the edit
    std::vector<std::pair<int, int>> moves; // (from, to): a survivor from the tail into a hole, to < from
    std::vector<int> addedAt;               // where added item j goes

    // Per old item: its index after the edit, -1 if removed (O(old count) integers).
    std::vector<int> newIndex(int count, const std::vector<int>& removed) const;
    // The same into `to` (its content is replaced), whose storage a caller keeps between edits.
    void newIndex(int count, const std::vector<int>& removed, std::vector<int>& to) const;
};

// The places for an array of `count` items that loses `removed` (ascending, distinct, in
// range) and gains `added` items: added item j takes hole removed[j]; more added items than
// holes go after the old end; holes left over below the new end take the survivors beyond it,
// in ascending order. Depends only on its arguments (same edit, same order).
HoleFilling fillHoles(int count, const std::vector<int>& removed, int added);

} // namespace shatter::geometry
