#pragma once
// When a link breaks and how loads weaken it (source 002 §3.2): "In case the constraint force
// for a connection is greater than the current connection strength, that connection is
// removed. Otherwise, the existing connection strength is weakened by the amount of the
// constraint force applied on it. Any connection for which the resulting connection strength
// is weaker than a predefined threshold is removed."
#include <shatter/plugin/lattice/Lattice.h>

#include <cmath>

namespace shatter::lattice {

struct BreakingSettings {
    // Weakening by load, applied once per step after the forces have settled. The source
    // weakens every surviving link by its force; applied every step, that would wear a wall
    // down under its own weight in a fraction of a second, so only loads of at least
    // `weakeningOnset` of a link's current capacity weaken it (impacts, not rest).
    bool weakenByLoad = true;
    double weakeningOnset = 0.5;   // fraction of the current capacity, in (0, 1]
    // The source's "predefined threshold": a link whose strength falls below this fraction of
    // its base strength is removed.
    double removalFraction = 0.05; // in [0, 1)
    // Solves per step at most: after breaks the forces are solved again until nothing more
    // breaks or this many solves have run.
    int maxRounds = 64;

    void check(const std::string& body) const;
};

// The link's force expressed as tension-equivalent newtons (compression divided by the
// ratio), which is what a load takes off its strength.
inline double tensileEquivalent(double lambda, double compressionRatio) {
    return lambda < 0.0 ? -lambda : lambda / compressionRatio;
}

// Force over capacity of a link of the given current strength (N) carrying multiplier λ (> 1
// breaks it): tension (λ < 0) is measured against the strength, compression against
// strength × compressionRatio. It takes the strength, not the Link: passes over a system's rows
// read the strengths gathered once instead of each row's 150-byte Link.
inline double utilisation(double strength, double lambda, double compressionRatio) {
    const double force = tensileEquivalent(lambda, compressionRatio);
    return strength > 0.0 ? force / strength : (force > 0.0 ? INFINITY : 0.0);
}


} // namespace shatter::lattice
