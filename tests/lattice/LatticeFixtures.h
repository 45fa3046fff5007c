#pragma once
// Small meshes with known answers, shared by the lattice tests.
#include <shatter/plugin/lattice/TetMesh.h>

#include <Eigen/Core>

#include <numeric>
#include <vector>

namespace shatter::lattice::test {

// 0, 1, ..., n - 1: every particle (or link) of a lattice, for a piece or system of the whole.
inline std::vector<int> indices(int n) {
    std::vector<int> v(n);
    std::iota(v.begin(), v.end(), 0);
    return v;
}

// A vertical chain of `count` tets whose centroids all lie on the y axis, `step` apart: node k
// is at (x, z) = (1,0), (0,1), (-1,0), (0,-1) (repeating) and y = k·step, and tet k is nodes
// k..k+3. Consecutive tets share a face; others share at most an edge. Every link is vertical,
// so a hanging or standing chain carries exactly the weight below or above each link.
inline TetMesh verticalChain(int count, double step = 0.5) {
    static const double ux[4] = {1, 0, -1, 0}, uz[4] = {0, 1, 0, -1};
    std::vector<Eigen::Vector3d> nodes;
    for (int k = 0; k < count + 3; ++k) nodes.emplace_back(ux[k % 4], k * step, uz[k % 4]);
    std::vector<Tet> tets;
    for (int k = 0; k < count; ++k) {
        Tet t{k, k + 1, k + 2, k + 3};
        const Eigen::Vector3d& a = nodes[t[0]];
        if ((nodes[t[1]] - a).dot((nodes[t[2]] - a).cross(nodes[t[3]] - a)) < 0) std::swap(t[1], t[2]);
        tets.push_back(t);
    }
    return makeTetMesh("chain", std::move(nodes), std::move(tets));
}

// One tet with a neighbour on each of its four faces (five tets, four links).
inline TetMesh starOfFive() {
    std::vector<Eigen::Vector3d> nodes = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    std::vector<Tet> tets = {{0, 1, 2, 3}};
    // Mirror the opposite corner of each face through the face's centroid.
    const auto faces = outwardFaces(tets[0]);
    for (int k = 0; k < 4; ++k) {
        const auto& f = faces[k];
        const Eigen::Vector3d c = (nodes[f[0]] + nodes[f[1]] + nodes[f[2]]) / 3.0;
        nodes.push_back(2.0 * c - nodes[tets[0][k]]);
        // The face seen from the new tet is reversed: (f0, f2, f1) then the new node.
        tets.push_back({f[0], f[1], f[2], int(nodes.size()) - 1});
    }
    for (Tet& t : tets) {
        const Eigen::Vector3d& a = nodes[t[0]];
        if ((nodes[t[1]] - a).dot((nodes[t[2]] - a).cross(nodes[t[3]] - a)) < 0) std::swap(t[1], t[2]);
    }
    return makeTetMesh("star", std::move(nodes), std::move(tets));
}

} // namespace shatter::lattice::test
