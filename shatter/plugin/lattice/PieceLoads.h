#pragma once
// The loads on a lattice piece in one step (source 002 §3): gravity on every free particle,
// and each impact's force (the contact impulse over the step) on the particles nearest to
// where it hit, weighted by inverse distance. All in the piece's mesh coordinates.
#include <shatter/plugin/lattice/Lattice.h>
#include <shatter/plugin/lattice/LatticePiece.h>

#include <Eigen/Core>

#include <span>
#include <utility>
#include <vector>

namespace shatter::lattice {

// A contact's push on a piece.
struct Impact {
    Eigen::Vector3d point;  // where (mesh coordinates)
    Eigen::Vector3d force;  // N (the contact's impulse on the piece over the step)
    int particle = -1;      // the tet the contact touched, as a position in piece.particles, or -1
};

// 3 loads per particle of the piece (in piece.particles order): `gravity` (m/s², mesh axes)
// times the mass of every free particle, plus each impact spread over `impactParticles`
// nearest particles (nearestParticles) by addPointForce. Formed in the piece's kept buffer
// (LatticePiece::loads) and valid until the next call for the piece: when g has the same bits
// as last time, only the particles of the last and this step's impacts are written.
const Eigen::VectorXd& pieceLoads(const Lattice& lattice, LatticePiece& piece, const Eigen::Vector3d& gravity,
                                  std::span<const Impact> impacts, int impactParticles);

// The k particles of the piece nearest to `point` (positions in piece.particles, with squared
// distances, nearest first). When the touched tet is known and k <= 5, the candidates are that
// tet and its face neighbours in the piece, which is exact for every contact on the tet and
// costs O(1); otherwise the piece's grid is searched.
std::vector<std::pair<double, int>> nearestParticles(const Lattice& lattice, LatticePiece& piece,
                                                     const Eigen::Vector3d& point, int particle, int k);

// Spreads a force at a point over `nearest` (squared distances and particle positions, nearest
// first) with inverse-distance weights summing to one, and adds it to `loads` (3 per particle).
void addPointForce(const std::vector<std::pair<double, int>>& nearest, const Eigen::Vector3d& force,
                   Eigen::VectorXd& loads);

// Whether some particle's load moved, since the piece's last analysis (piece.analysedLoads), by
// more than `fraction` of the strength of its weakest unbroken link. In this lattice a link
// carries mostly the loads of its own two particles (forces fall off by about 3 per link away
// from a load), so smaller changes leave every link's force within about that fraction of
// where it was; resting and jittering pieces then cost next to nothing. True when the piece
// was never analysed.
bool loadsChanged(const Lattice& lattice, const LatticePiece& piece, const Eigen::VectorXd& loads, double fraction);

} // namespace shatter::lattice
