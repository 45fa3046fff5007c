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
                    EXPECT_EQ(got, expect); // distances by bits, and the indices
                }
            }
        }
}

// Points on a regular lattice, queried at points equally far from several of them (lattice
// points, cell centres, edge midpoints, far outside): the ties go to the lower index, as in a
// sort of every (distance, index) pair, and far queries stop at the same k.
TEST(NearestParticles, BreaksTiesByIndexOnARegularLattice) {
    std::vector<Eigen::Vector3d> pts;
    for (int x = 0; x < 12; ++x)
        for (int y = 0; y < 9; ++y)
            for (int z = 0; z < 7; ++z) pts.emplace_back(0.25 * x, 0.25 * y, 0.25 * z);
    const NearestParticles grid(pts);
    const std::vector<Eigen::Vector3d> queries = {{0.0, 0.0, 0.0},       {0.125, 0.125, 0.125}, {1.0, 1.0, 0.875},
                                                  {2.75, 2.0, 1.5},      {1.375, 0.5, 0.625},   {-3.0, 1.0, 0.75},
                                                  {1.5, 40.0, -2.0},     {0.625, 0.625, 0.625}, {2.8, 2.1, 1.6}};
    for (const Eigen::Vector3d& p : queries)
        for (int k : {1, 2, 4, 7, 30, 756, 1000}) EXPECT_EQ(grid.nearest(p, k), bruteForce(pts, p, k)) << p.transpose() << " k " << k;
}

} // namespace
} // namespace shatter::lattice
