#pragma once
// What a broken piece becomes (source 002 §3, §5): its connected components, each with exact
// mass properties from its tets (the motion it inherits is geometry::partState), and the surface
// a renderer draws (the tets' faces that border no tet of the same fragment: the outer
// surface and the crack faces). Single-tet fragments are kept, as the source argues: dropping
// them leaves gaps around the cracks.
#include <shatter/plugin/geometry/MassProperties.h>
#include <shatter/plugin/lattice/Lattice.h>
#include <shatter/plugin/lattice/LatticePiece.h>

#include <array>
#include <vector>

namespace shatter::lattice {

// Components of `particles` joined by unbroken links; each sorted, ordered by their smallest
// particle. O(particles + links).
std::vector<std::vector<int>> connectedComponents(const Lattice& lattice, const std::vector<int>& particles);

// Exact mass, centre of mass and inertia (about the centre, mesh axes) of one tet and of a set.
geometry::MassProperties tetMassProperties(const TetMesh& mesh, const Tet& tet, double density);
geometry::MassProperties pieceMassProperties(const Lattice& lattice, const std::vector<int>& particles);
// The same sum (same bits) from each tet's mass properties computed beforehand
// (tetMass[p] = tetMassProperties of tet p): a body that sums its 50,000-tet rest again after
// each break keeps them.
geometry::MassProperties pieceMassProperties(const std::vector<geometry::MassProperties>& tetMass,
                                             const std::vector<int>& particles);

// The diameter (m) of the sphere about the piece's centre of mass `centre` (mesh coordinates)
// that holds every node of its tets: twice the farthest node's distance. What a player sees of
// a piece's size whatever its shape or orientation (a flat shard counts by its width).
double pieceSize(const Lattice& lattice, const std::vector<int>& particles, const Eigen::Vector3d& centre);

// The faces of the piece's tets that border no tet of the piece (outer surface and crack
// faces), counter-clockwise seen from outside.
std::vector<std::array<int, 3>> surfaceFaces(const Lattice& lattice, const std::vector<int>& particles);

// How far the piece is from convex (m): the largest distance by which one of its nodes lies in
// front of the plane of one of its surface faces. 0 (up to rounding) exactly when the piece is
// convex: if every node is behind every surface face, a segment from inside the piece to a
// point of its convex hull cannot leave the piece through a face (it would end in front of
// that face's plane), so the piece is its hull. O(surface faces × nodes): for small pieces.
double convexityDefect(const Lattice& lattice, const std::vector<int>& particles);

// Whether the piece may collide as its convex hull: convexityDefect at most `tolerance` times
// the edge of a cube of the piece's volume, so the hull overfills the piece by a sliver of at
// most that relative thickness. Pieces of more than `maxTets` tets are not tested (false).
bool isConvexPiece(const Lattice& lattice, const std::vector<int>& particles, double tolerance, int maxTets);

// The index of the part with the most particles (the first such) in `parts` (not empty): the
// only part that may keep a split piece's body (partKeepingTheBody below; also where a moving
// piece's parts beyond the fragment budget stay, LatticeSystem).
int largestPart(const std::vector<std::vector<int>>& parts);

// Which part of a piece that split keeps the piece's body, or -1 when every part gets a new
// one. The big rest of a wall or a table top is split again and again as pieces break away;
// building each of its thousands of tets anew every time cost most of the shatter frame (the
// allocations of its child hulls alone). So the largest part keeps the body when it holds more
// than half of the piece's tets, is anchored exactly when the piece is (a static body stays
// static), and is not convex (a convex part collides as a hull, a new shape anyway;
// `tolerance` and `maxTets` as isConvexPiece).
int partKeepingTheBody(const Lattice& lattice, const LatticePiece& piece, const std::vector<std::vector<int>>& parts,
                       double tolerance, int maxTets);

} // namespace shatter::lattice
