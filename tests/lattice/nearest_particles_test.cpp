// The nearest-particle grid against brute force, on solid, flat and tiny point sets.
#include <shatter/plugin/lattice/NearestParticles.h>
#include <shatter/plugin/lattice/Random.h>

#include <gtest/gtest.h>

#include <algorithm>

namespace shatter::lattice {
namespace {

std::vector<std::pair<double, int>> bruteForce(const std::vector<Eigen::Vector3d>& pts, const Eigen::Vector3d& p, int k) {
    std::vector<std::pair<double, int>> all;
    for (int i = 0; i < int(pts.size()); ++i) all.emplace_back((pts[i] - p).squaredNorm(), i);
    std::sort(all.begin(), all.end());
    all.resize(std::min<size_t>(size_t(k), all.size()));
    return all;
}

TEST(NearestParticles, MatchesBruteForce) {
    Random random(9);
    const std::vector<Eigen::Vector3d> scales = {{1.7, 1.0, 0.4}, {1.0, 0.0, 1.0}, {2.0, 1e-9, 1e-9}, {0.1, 0.1, 0.1}};
    for (const Eigen::Vector3d& s : scales)
        for (int n : {1, 3, 50, 500, 3000}) {
            std::vector<Eigen::Vector3d> pts;
            for (int i = 0; i < n; ++i)
                pts.emplace_back(random.uniform() * s.x(), random.uniform() * s.y(), random.uniform() * s.z());
            const NearestParticles grid(pts);
            for (int q = 0; q < 40; ++q) {
                // Queries inside and well outside the points' box.
                const Eigen::Vector3d p(random.uniform(-0.5, 2.5), random.uniform(-0.5, 1.5), random.uniform(-0.5, 1.5));
                for (int k : {1, 4, 7}) {
                    const auto expect = bruteForce(pts, p, k);
                    const auto got = grid.nearest(p, k);
                    ASSERT_EQ(got.size(), expect.size());
                    for (size_t j = 0; j < got.size(); ++j) EXPECT_DOUBLE_EQ(got[j].first, expect[j].first);
                }
            }
        }
}

} // namespace
} // namespace shatter::lattice
