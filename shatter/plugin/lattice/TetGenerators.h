#pragma once
// Built-in tet meshes for boxes, slabs and cylinders, so that a scene needs no mesh file.
#include <shatter/plugin/lattice/TetMesh.h>

#include <cstdint>

namespace shatter::lattice {

struct GeneratorOptions {
    std::string name;           // mesh name for messages ("" = "box", "slab", "cylinder")
    // Random displacement of every node, as a fraction of the local cell size along each axis
    // (uniform in [-jitter, jitter]), so the lattice is not uniform. Nodes on the surface move
    // only within it, so the outer shape is kept. Allowed range [0, 0.2]: every tet keeps a
    // positive volume (a Kuhn tet's smallest height is 0.71 of the cell, a node moves at most
    // sqrt(3) * 0.2 = 0.35 of it).
    double jitter = 0.0;
    std::uint64_t seed = 1;     // seed of the jitter
};

// A box of full side lengths `extent` (m) centred at the origin, cells.x × cells.y × cells.z
// cubes each split into six tets around its main diagonal (Kuhn), which tile conformingly.
// 6·cells tets; links ≈ 2 per tet inside. Throws shatter::InputError for a non-positive or
// non-finite extent, a cell count below 1 or above 200 per axis, or a jitter out of range.
TetMesh tetBox(const Eigen::Vector3d& extent, const Eigen::Vector3i& cells, const GeneratorOptions& options = {});

// A slab in the x-z plane, `thickness` (m) along y, centred at the origin: a box with `layers`
// cells across the thickness and square-ish cells of about `cellSize` (m) in the plane.
TetMesh tetSlab(double sizeX, double sizeZ, double thickness, double cellSize, int layers = 1,
                const GeneratorOptions& options = {});

// A cylinder along y of `radius` and `height` (m), centred at the origin: `rings` rings of
// nodes around the axis (ring k has 6k nodes, a disc of triangles of near-equal size),
// `layers` layers along y, each triangular prism split into three tets by the smallest-index
// rule (Dompierre et al. 1999), which makes neighbouring prisms agree on shared faces.
TetMesh tetCylinder(double radius, double height, int rings, int layers, const GeneratorOptions& options = {});

} // namespace shatter::lattice
