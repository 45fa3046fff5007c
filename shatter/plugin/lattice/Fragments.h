#pragma once
// What a broken piece becomes (source 002 §3, §5): its connected components, each with exact
// mass properties from its tets, the rigid motion it inherits from the piece, and the surface
// a renderer draws (the tets' faces that border no tet of the same fragment: the outer
// surface and the crack faces). Single-tet fragments are kept, as the source argues: dropping
// them leaves gaps around the cracks.
#include <shatter/plugin/geometry/MassProperties.h>
#include <shatter/plugin/lattice/Lattice.h>

#include <array>
#include <vector>

namespace shatter::lattice {

// Components of `particles` joined by unbroken links; each sorted, ordered by their smallest
// particle. O(particles + links).
std::vector<std::vector<int>> connectedComponents(const Lattice& lattice, const std::vector<int>& particles);

// Exact mass, centre of mass and inertia (about the centre, mesh axes) of one tet and of a set.
geometry::MassProperties tetMassProperties(const TetMesh& mesh, const Tet& tet, double density);
geometry::MassProperties pieceMassProperties(const Lattice& lattice, const std::vector<int>& particles);

// A rigid body's state in one frame: mass, centre of mass, inertia about the centre (frame
// axes), linear and angular velocity.
struct RigidState {
    double mass = 0.0;
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();
    Eigen::Vector3d velocity = Eigen::Vector3d::Zero();
    Eigen::Vector3d angularVelocity = Eigen::Vector3d::Zero();

    Eigen::Vector3d linearMomentum() const { return mass * velocity; }
    // About the frame's origin.
    Eigen::Vector3d angularMomentum() const { return centre.cross(linearMomentum()) + inertia * angularVelocity; }
};

// The state a fragment with mass properties `part` (same frame) takes from its parent: the
// parent's velocity at the fragment's centre of mass (v + ω × (c_f - c)) and the parent's ω.
// Over all fragments of a parent, mass and linear and angular momentum add up to the parent's
// exactly (parallel-axis theorem), up to rounding.
RigidState fragmentState(const RigidState& parent, const geometry::MassProperties& part);

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

} // namespace shatter::lattice
