#pragma once
// Particles cut by an initial crack are split along it (issue 20).
//
// A particle stands for the square of side h (the lattice spacing) around it, and the
// line-crossing test (LineCrossing.h) gives the whole particle to the side its centre lies
// on. Where a crack line passes between lattice rows at an arbitrary height, the material
// each side holds then ends at the row boundary, not at the crack: a crack a third of a cell
// above a grid line with 2 particles per cell has the material interface 1/6 cell above the
// crack line, so the two faces are not mirror images and a symmetric crack in pure tension
// showed |K_II|/K_I ≈ 0.04 (measured with 3 particles per cell per axis: 1.5% a quarter cell
// off, 2.6% with a particle row on the line, 0.6% a third off where the rows are symmetric).
// Splitting each cut square into its two parts (each a particle at its part's centroid with
// its share of the area and mass) puts the material interface on the crack line.
//
// Only the squares the crack crosses whole are split (entering and leaving through the
// square's outline; a square holding a crack end is left whole), along the chord between the
// entry and exit points (exact for a straight crack). A part smaller than `minimumShare` of
// the square is not split off: it stays with the other part (the interface moves by at most
// that share of h).
#include <shatter/plugin/mpm/Crack.h>
#include <shatter/plugin/mpm/Particles.h>

#include <vector>

namespace shatter::mpm {

// Splits the particles of `particles` cut by `cracks` (all at rest, in the reference
// configuration, spacing h). The part on the crack's "below" side keeps the particle's index
// (loads built earlier stay valid); the "above" parts are appended, in particle order.
// Returns the number of particles split.
size_t splitParticlesAtCracks(const std::vector<Crack>& cracks, double h, Particles& particles,
                              double minimumShare = 0.05);

// After tip `tip` of `crack` grew by one step: splits the particles whose squares the crack
// now crosses whole near that step (the square that held the old tip, and any the step
// crossed), in the particle's reference configuration mapped through its deformation
// gradient; both parts keep the particle's state (velocity, F, C). Without this the faces of
// a grown crack end at the lattice rows, not at the crack line: a crack line 1/3 cell off
// the grid lines then acts as if it were on the row boundary (1/2 cell off) while the J
// contour and the growth direction follow the drawn line, which read as mode II (K_II/K_I
// about +2% after a few steps). Parts of a square split before (volume below the whole)
// are not split again. Returns the number of particles split.
size_t splitParticlesAtGrowth(const Crack& crack, int tip, double h, Particles& particles, double minimumShare = 0.05);

} // namespace shatter::mpm
