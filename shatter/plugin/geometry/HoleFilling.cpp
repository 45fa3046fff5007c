#include <shatter/plugin/geometry/HoleFilling.h>

#include <algorithm>

namespace shatter::geometry {

HoleFilling fillHoles(int count, const std::vector<int>& removed, int added) {
    HoleFilling out;
    const int r = int(removed.size());
    out.size = count - r + added;
    const int filled = std::min(r, added);
    out.addedAt.reserve(size_t(added));
    // removed[j] <= count - r + j < size for j < added: every hole an added item takes stays.
    for (int j = 0; j < filled; ++j) out.addedAt.push_back(removed[size_t(j)]);
    for (int j = filled; j < added; ++j) out.addedAt.push_back(count + (j - r));
    // Holes left below the new end: as many as survivors at or beyond it (both fill [0, size)).
    int from = out.size;
    size_t skip = size_t(std::lower_bound(removed.begin(), removed.end(), out.size) - removed.begin());
    for (int k = filled; k < r && removed[size_t(k)] < out.size; ++k) {
        while (skip < removed.size() && removed[skip] == from) {
            ++skip;
            ++from;
        }
        out.moves.emplace_back(from++, removed[size_t(k)]);
    }
    return out;
}

std::vector<int> HoleFilling::newIndex(int count, const std::vector<int>& removed) const {
    std::vector<int> to;
    newIndex(count, removed, to);
    return to;
}

void HoleFilling::newIndex(int count, const std::vector<int>& removed, std::vector<int>& to) const {
    to.resize(static_cast<size_t>(count)); // every entry is written below
    for (int i = 0; i < count; ++i) to[size_t(i)] = i;
    for (int i : removed) to[size_t(i)] = -1;
    for (const auto& [from, hole] : moves) to[size_t(from)] = hole;
}

} // namespace shatter::geometry
