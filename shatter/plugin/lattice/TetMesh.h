#pragma once
// A tetrahedral mesh as the lattice reads it (source 002 §2): nodes and four-node elements.
#include <Eigen/Core>
#include <Eigen/Geometry>

#include <array>
#include <string>
#include <utility>
#include <vector>

namespace shatter::lattice {

using Tet = std::array<int, 4>;

struct TetMesh {
    std::string name = "tet mesh";       // used in every error message about this mesh
    std::vector<Eigen::Vector3d> nodes;  // metres
    std::vector<Tet> tets;               // node indices, positive orientation (see signedVolume)
    std::vector<std::string> warnings;   // what the reader changed (never silently)
    // Element numbers as written in the source file, for messages; empty: 0-based indices.
    std::vector<long> tetNumbers;
};

// "tetrahedron N" with the file's numbering when the mesh has one.
std::string tetLabel(const TetMesh& mesh, int t);

// det(b - a, c - a, d - a) / 6: positive when d lies on the side of triangle (a, b, c) that
// its counter-clockwise normal points to. Every tet of a valid mesh is positive.
double signedVolume(const TetMesh& mesh, const Tet& tet);
Eigen::Vector3d centroid(const TetMesh& mesh, const Tet& tet);

// Faces of a positively oriented tet, counter-clockwise seen from outside; face k is the one
// opposite corner k.
std::array<std::array<int, 3>, 4> outwardFaces(const Tet& tet);

// A tet mesh from plain arrays (node coordinates, zero-based corner indices). Throws
// shatter::InputError naming `name` and the element for anything validateTetMesh rejects.
TetMesh makeTetMesh(std::string name, std::vector<Eigen::Vector3d> nodes, std::vector<Tet> tets);

// Checks everything the lattice relies on and throws shatter::InputError naming the mesh and
// the first offending node or element: no nodes or tets, a non-finite coordinate, an index
// out of range or repeated in one tet, a tet whose volume is not finite (coordinates too large),
// a degenerate tet (volume below 1e-9 of its longest edge cubed), an inverted tet (negative
// orientation), two tets with the same four nodes in any order, a face shared by more than two tets,
// and a mesh in more than one piece (every tet must reach every other across shared faces).
void validateTetMesh(const TetMesh& mesh);

// What is wrong with element t (index out of range or repeated, non-finite volume, degenerate, inverted), or an
// empty string. The text starts with the problem, not the element, so readers can prefix it.
std::string tetProblem(const TetMesh& mesh, int t);

// The first tet that repeats an earlier one's four nodes in any order, as (earlier, later), or
// (-1, -1); and the problem text for `later` (a repeated tet would double the mass there).
std::pair<int, int> duplicateTets(const TetMesh& mesh);
std::string duplicateProblem(const TetMesh& mesh, int earlier);

// The volume ratio below which a tet counts as degenerate: V / Lmax³ (a regular tet has 0.118).
constexpr double kDegenerateVolumeRatio = 1e-9;

} // namespace shatter::lattice
