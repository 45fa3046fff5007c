#pragma once
// A minimum fragment size in metres. A hit on a tet body breaks the links around the crater and
// its tets come loose one by one: about 2% of the tets of Spot became fragments in the first hit
// whatever the mesh (44 / 184 / 495 / 925 single tets for 2k / 10k / 23k / 55k tets), so the
// fragment count, and with it Bullet's broadphase pairs and contacts, grew with the resolution
// while the crater stayed the same. Here the parts of a piece that broke are merged so that no
// loose part is smaller than the minimum size: small parts next to each other (across the links
// that just broke between them) are grown into clusters of at least that size; what cannot grow
// that far stays with its neighbour (the part it shares the largest broken faces with, the
// anchored rest included: it stays attached). The links inside a merged group are joined for
// good (Lattice::joinLink), so the group is one rigid piece that never falls into its small
// parts again: its tets leave only together. Size is lattice::pieceSize: the diameter of the
// sphere about the part's centre of mass that holds its nodes.
#include <shatter/plugin/lattice/Lattice.h>
#include <shatter/plugin/lattice/LatticePiece.h>

#include <vector>

namespace shatter::lattice {

// The parts `piece` falls into after its links broke: its connected components (from
// connectedComponents), the small ones merged into groups, the links between the merged parts
// of a group joined (Lattice::joinLink). Each part sorted, ordered by its smallest particle.
// When everything stays one part but links were joined, the piece's system is rebuilt with them
// (λ carried over by link). Deterministic: it depends only on the piece and the lattice, never
// on addresses or hash order. A component is small when it holds no fixed particle and its size
// is below `minSize` (m); components are neighbours when a (broken) link joins them.
// - Each small component not yet taken, in order, seeds a cluster that takes the untaken small
//   one next to it whose centre of mass is nearest the cluster's, one at a time, until the
//   cluster reaches `minSize` or has no untaken small neighbour.
// - Then, in rounds, every group still below `minSize` that holds no component of at least that
//   size (and no fixed particle) joins the neighbouring group it shares the most broken face
//   area with, until none has a neighbour left (then the whole piece is one group: it does not
//   split).
// minSize <= 0 or a single component: the components themselves.
std::vector<std::vector<int>> fragmentParts(Lattice& lattice, LatticePiece& piece, double minSize);

} // namespace shatter::lattice
