#pragma once
// A soft-body test block shared by the oriented tests.
#include <shatter/plugin/geometry/PhysicalMesh.h>

#include <Eigen/Core>
#include <vector>

namespace shatter::test {

// Closed cubes of side h at the integer cells given (cell (i, j, k) spans [i, i+1] h along x,
// and so on), offset by (x, y, 0); cubes shrunk by `inset` so that neighbours share no vertex:
// the mesh builder welds shared vertices into one part, and the cubes must stay separate
// closed convex parts (still connected: the default gap of 0.1 µm is far below the contact
// tolerance).
inline geometry::PhysicalMesh cubesAt(const std::vector<Eigen::Vector3i>& cells, double h, double x, double y,
                                      double inset = 1e-7) {
    std::vector<Eigen::Vector3d> positions;
    std::vector<std::vector<int>> faces;
    for (const Eigen::Vector3i& cell : cells) {
        const int base = int(positions.size());
        for (int c = 0; c < 8; ++c) {
            const Eigen::Vector3d corner(c & 1, (c >> 1) & 1, (c >> 2) & 1);
            const Eigen::Vector3d in = (Eigen::Vector3d::Ones() - 2 * corner) * inset;
            positions.push_back(cell.cast<double>() * h + corner * h + in + Eigen::Vector3d(x, y, 0));
        }
        for (const auto& f : std::vector<std::vector<int>>{
                 {0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}}) {
            std::vector<int> face;
            for (int c : f) face.push_back(base + c);
            faces.push_back(face);
        }
    }
    geometry::PhysicalMeshSettings s;
    s.density = 1000;
    return geometry::buildPhysicalMesh("jelly", positions, faces, s);
}

// An n × n × n block of such cubes, lowest corner at (x, y, 0).
inline geometry::PhysicalMesh cubes(int n, double h, double x, double y, double inset = 1e-7) {
    std::vector<Eigen::Vector3i> cells;
    for (int k = 0; k < n; ++k)
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) cells.emplace_back(i, j, k);
    return cubesAt(cells, h, x, y, inset);
}

} // namespace shatter::test
