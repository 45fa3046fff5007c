#pragma once
// Small bodies of box primitives for the oriented-particle tests.
#include <shatter/plugin/geometry/JointBoxes.h>
#include <shatter/plugin/oriented/OrientedSolver.h>

#include <random>

namespace shatter::oriented::test {

// An nx × ny × nz block of cubes of side `cell` (m), its lowest corner at `origin`, every
// pair of touching cubes (faces, edges or corners) connected, as the physical mesh does.
struct CubeBlock {
    std::vector<geometry::ConvexPolyhedron> primitives;
    std::vector<std::pair<int, int>> connections;
};

inline CubeBlock cubeBlock(int nx, int ny, int nz, double cell, const Eigen::Vector3d& origin = Eigen::Vector3d::Zero()) {
    CubeBlock block;
    auto index = [&](int i, int j, int k) { return (k * ny + j) * nx + i; };
    for (int k = 0; k < nz; ++k)
        for (int j = 0; j < ny; ++j)
            for (int i = 0; i < nx; ++i) {
                geometry::OrientedBox box;
                box.pose.translation() = origin + cell * Eigen::Vector3d(i + 0.5, j + 0.5, k + 0.5);
                box.halfExtents = Eigen::Vector3d::Constant(cell / 2);
                block.primitives.push_back(geometry::boxPolyhedron(box));
            }
    for (int k = 0; k < nz; ++k)
        for (int j = 0; j < ny; ++j)
            for (int i = 0; i < nx; ++i)
                for (int dk = 0; dk <= 1; ++dk)
                    for (int dj = -1; dj <= 1; ++dj)
                        for (int di = -1; di <= 1; ++di) {
                            const int a = index(i, j, k);
                            const int ii = i + di, jj = j + dj, kk = k + dk;
                            if (ii < 0 || jj < 0 || ii >= nx || jj >= ny || kk >= nz) continue;
                            const int b = index(ii, jj, kk);
                            if (b > a) block.connections.push_back({a, b});
                        }
    return block;
}

inline OrientedSolver blockSolver(const CubeBlock& block, const SolverSettings& settings = {}, double density = 1000.0) {
    return OrientedSolver("block", particlesFromPrimitives(block.primitives, density, "block"), block.connections,
                          settings);
}

inline Eigen::Vector3d randomVector(std::mt19937& rng, double scale) {
    std::uniform_real_distribution<double> u(-scale, scale);
    return {u(rng), u(rng), u(rng)};
}

inline Eigen::Quaterniond randomRotation(std::mt19937& rng) {
    std::normal_distribution<double> n;
    Eigen::Quaterniond q(n(rng), n(rng), n(rng), n(rng));
    return q.normalized();
}

} // namespace shatter::oriented::test
