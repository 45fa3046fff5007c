#pragma once
// Dynamic weakening around a break: the source's changeConnectionStrengths (002 §3.2). When a
// link breaks, the links around it lose strength, less with every step away from the crack,
// and at each node one randomly chosen neighbour link loses more, so cracks branch and wander
// instead of following the mesh's regularity.
//
//   changeConnectionStrengths(n1, n2, change):
//     weaken link (n1, n2) by change;  change ← α · change
//     for node in {n1, n2}:
//       pick a random neighbour link of node; weaken it by Θ = θ · change (Θ > change)
//       if change ≥ τ: for every other neighbour link (node, m): changeConnectionStrengths(node, m, change)
//
// The first call is made for the broken link itself with change = initialFraction × its base
// strength (the broken link is already gone, so its own weakening is moot). The source does
// not say what "change" starts at nor what τ is relative to; here τ = tauFraction × the
// initial change, so the spreading always reaches the same number of steps.
#include <shatter/plugin/lattice/Lattice.h>
#include <shatter/plugin/lattice/Random.h>

#include <string>
#include <vector>

namespace shatter::lattice {

struct DamageSpreadingSettings {
    bool enabled = true;
    double initialFraction = 0.3; // first change, as a fraction of the broken link's base strength
    double alpha = 0.5;           // decay per step, in (0, 1)
    double theta = 2.0;           // the random neighbour is weakened by theta × change; > 1
    double tauFraction = 0.2;     // stop spreading below tauFraction × the first change, in (0, 1)

    void check(const std::string& body) const;
};

// Spreads damage from the broken link `link` (source algorithm above). Links whose strength
// drops below removalFraction × base strength are broken and appended to `removed`.
// Deterministic for a given state of `random`; neighbours are visited in link order.
void spreadDamage(Lattice& lattice, int link, const DamageSpreadingSettings& settings, double removalFraction, Random& random,
                  std::vector<int>& removed);

} // namespace shatter::lattice
