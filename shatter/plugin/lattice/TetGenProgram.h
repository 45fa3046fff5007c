#pragma once
// Tetrahedralizing an arbitrary closed surface by running the external `tetgen` program
// (Debian package "tetgen"). TetGen is AGPL, so Shatter never links it: it writes the surface
// to a temporary .smesh file, runs the program, and reads its .node/.ele output back with
// readTetGen. Nothing in Shatter needs the program; this is for meshes the built-in
// generators cannot make.
#include <shatter/plugin/lattice/TetMesh.h>

#include <string>
#include <vector>

namespace shatter::lattice {

struct TetGenProgramOptions {
    std::string program = "tetgen"; // looked up on PATH
    double radiusEdgeRatio = 1.4;   // -q: quality bound (TetGen's default 2.0; smaller = rounder tets); 0 = none (-p alone: slivers)
    double maxVolume = 0.0;         // -a: largest tet volume in m³ (0 = no bound)
};

// Whether `program` is on PATH (or is a path to an executable).
bool tetgenAvailable(const std::string& program = "tetgen");

// Tetrahedralizes the closed surface (polygons over `positions`, any orientation) named
// `name`. Throws shatter::InputError naming the surface when the program is missing or fails,
// or when its output is not a valid mesh.
TetMesh tetrahedralize(const std::string& name, const std::vector<Eigen::Vector3d>& positions,
                       const std::vector<std::vector<int>>& faces, const TetGenProgramOptions& options = {});

} // namespace shatter::lattice
