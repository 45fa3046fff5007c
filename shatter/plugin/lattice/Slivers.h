#pragma once
// Sliver tets (issue 19): a tet mesher run without a quality bound (TetGen -p, the usual first
// try) leaves flat tets whose four corners lie near one plane: 1,599 of the 10,274 tets of
// Spot have a quality below 0.01. Such a tet has almost no mass and no thickness; broken off on
// its own it became a rigid body whose contacts Bullet cannot resolve (the issue saw fragments
// at 4e8 m/s). Before anything breaks, each sliver is bound to its best neighbour: their link
// can never break, so a sliver only ever leaves with that neighbour (as if merged into its
// particle), while its mass, its own links and the mesh stay as they are.
#include <shatter/plugin/lattice/Lattice.h>

#include <vector>

namespace shatter::lattice {

// 6·√2·V / L³ with L the tet's longest edge: 1 for a regular tet, 0 for a flat one. The
// degenerate limit of validateTetMesh (kDegenerateVolumeRatio) is 8.5e-9 on this scale.
double tetQuality(const TetMesh& mesh, const Tet& tet);

// Tets of quality below `threshold`, in increasing order.
std::vector<int> sliverTets(const TetMesh& mesh, double threshold);

struct SliverBinding {
    int slivers = 0;           // tets below the threshold
    std::vector<int> links;    // links made unbreakable, in increasing order
};

// Binds every tet of quality below `threshold` to its best neighbour, the one across its
// largest shared face that is not a sliver itself (a sliver among slivers only: across its
// largest face). A group of slivers bound only to each other is then bound, across its
// largest face to a tet outside it, until every group holds a tet above the threshold (or is
// the whole mesh). Bound links get infinite strength: nothing weakens or breaks them.
// `threshold` 0 binds nothing.
SliverBinding bindSlivers(Lattice& lattice, double threshold);

// The quality below which a tet counts as a sliver by default.
constexpr double kSliverQuality = 0.01;

} // namespace shatter::lattice
