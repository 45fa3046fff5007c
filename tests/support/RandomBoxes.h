#pragma once
// Seeded random axis-aligned boxes in [0, 10]³ with sides 0.05–1, for the box-tree tests.
#include <shatter/plugin/geometry/Aabb.h>

#include <random>
#include <vector>

namespace shatter::test {

inline std::vector<geometry::Aabb> randomBoxes(int n, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> pos(0.0, 10.0), size(0.05, 1.0);
    std::vector<geometry::Aabb> boxes(static_cast<size_t>(n));
    for (auto& b : boxes) {
        b.min = Eigen::Vector3d(pos(rng), pos(rng), pos(rng));
        b.max = b.min + Eigen::Vector3d(size(rng), size(rng), size(rng));
    }
    return boxes;
}

} // namespace shatter::test
