// ShapeMatchingGroups::removeConnections: the groups after connections broke (a tear, source
// 000 §3.6), edited in place instead of built again for the whole body.
#include <shatter/plugin/oriented/ShapeMatchingGroups.h>

#include <shatter/plugin/common/InputError.h>

#include <algorithm>
#include <string>

namespace shatter::oriented {

void ShapeMatchingGroups::removeConnections(const OrientedParticles& particles,
                                            std::span<const std::pair<int, int>> pairs) {
    const int n = size();
    std::vector<std::pair<int, int>> gone; // (group, member), sorted
    for (const auto& [a, b] : pairs) {
        if (a < 0 || b < 0 || a >= n || b >= n)
            throw InputError("shape matching: connection (" + std::to_string(a) + ", " + std::to_string(b) +
                             ") names a particle outside [0, " + std::to_string(n) + ")");
        if (a == b) continue;
        gone.emplace_back(a, b);
        gone.emplace_back(b, a);
    }
    if (gone.empty()) return;
    std::sort(gone.begin(), gone.end());
    gone.erase(std::unique(gone.begin(), gone.end()), gone.end());
    for (const auto& [g, member] : gone)
        if (!connected(g, member))
            throw InputError("shape matching: connection (" + std::to_string(g) + ", " + std::to_string(member) +
                             ") is not one of the groups'");
    // One pass from the first group that loses a member: the members after it move down; a
    // group's members stay its centre first, then the others ascending, as the constructor
    // orders them.
    std::vector<int> changed;
    auto next = gone.begin();
    int write = offsets_[gone.front().first];
    for (int g = gone.front().first; g < n; ++g) {
        const int begin = offsets_[g], end = offsets_[g + 1];
        offsets_[g] = write;
        const auto firstGone = next;
        for (int k = begin; k < end; ++k) {
            const int member = members_[size_t(k)];
            if (k > begin && next != gone.end() && next->first == g && next->second == member) {
                ++next;
                continue;
            }
            members_[size_t(write)] = member;
            ++write;
        }
        if (next != firstGone) changed.push_back(g);
    }
    offsets_[size_t(n)] = write;
    members_.resize(size_t(write));
    for (int g : changed) updateRest(g, particles);
}

} // namespace shatter::oriented
