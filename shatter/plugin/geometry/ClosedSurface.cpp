#include <shatter/plugin/geometry/ClosedSurface.h>

#include <algorithm>
#include <numeric>
#include <tuple>
#include <utility>

namespace shatter::geometry {

std::vector<int> coincidentRepresentatives(const std::vector<Eigen::Vector3d>& points) {
    std::vector<int> order(points.size());
    std::iota(order.begin(), order.end(), 0);
    auto key = [&](int i) { return std::make_tuple(points[i].x(), points[i].y(), points[i].z(), i); };
    std::sort(order.begin(), order.end(), [&](int a, int b) { return key(a) < key(b); });
    std::vector<int> rep(points.size());
    for (size_t k = 0; k < order.size(); ++k) {
        const bool sameAsPrevious = k > 0 && points[order[k]] == points[order[k - 1]];
        rep[order[k]] = sameAsPrevious ? rep[order[k - 1]] : order[k];
    }
    return rep;
}

bool isClosedSurface(const std::vector<std::vector<int>>& faces) {
    if (faces.size() < 4) return false;
    std::vector<std::pair<int, int>> edges;
    for (const auto& face : faces)
        for (size_t k = 0; k < face.size(); ++k) edges.emplace_back(face[k], face[(k + 1) % face.size()]);
    std::sort(edges.begin(), edges.end());
    if (std::adjacent_find(edges.begin(), edges.end()) != edges.end()) return false;
    for (const auto& [a, b] : edges)
        if (a == b || !std::binary_search(edges.begin(), edges.end(), std::make_pair(b, a))) return false;
    return true;
}

} // namespace shatter::geometry
