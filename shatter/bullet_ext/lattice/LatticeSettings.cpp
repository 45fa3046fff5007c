#include <shatter/bullet_ext/lattice/LatticeSettings.h>

#include <shatter/plugin/common/SettingCheck.h>

namespace shatter {

void RestSettings::check(const std::string& body) const {
    requireNonNegative(body, "sleep after (s)", sleepAfter);
    requireNonNegative(body, "sleep drift (m)", sleepDrift);
    requireNonNegative(body, "sleep turn (rad)", sleepTurn);
    requireNonNegative(body, "wake speed (m/s)", wakeSpeed);
    requireNonNegative(body, "wake drift (m)", wakeDrift);
    requireNonNegative(body, "wake mass ratio", wakeMassRatio);
}

void DebrisSettings::check(const std::string& body) const {
    requireNonNegative(body, "debris max size (m)", maxSize);
    requireNonNegative(body, "debris sleep after (s)", sleepAfter);
    requireNonNegative(body, "debris lifetime (s)", lifetime);
    requireAtLeast(body, "debris budget", budget, 0);
}

void LatticeSettings::check(int tetCount) const {
    const std::string& body = name;
    material.check(body);
    analysis.check(body);
    for (size_t i = 0; i < cleavingPlanes.size(); ++i) cleavingPlanes[i].check(body, int(i));
    noise.check(body);
    rigidBody.check(body);
    requireAtLeast(body, "impact particles", impactParticles, 1);
    requireNonNegative(body, "reanalysis fraction", reanalysisFraction);
    requirePositive(body, "max rotation per step (rad)", maxRotationPerStep);
    requireSetting(std::isfinite(hitSpeedFactor) && hitSpeedFactor >= 1.0, body, "hit speed factor", ">= 1 and finite",
                   hitSpeedFactor);
    requireNonNegative(body, "convex hull tolerance", convexHullTolerance);
    requireSetting(fragmentBudget == 0 || fragmentBudget >= 2, body, "fragment budget", "0 (no limit) or at least 2",
                   fragmentBudget);
    rest.check(body);
    debris.check(body);
    requirePositive(body, "anchor distance (m)", anchorDistance);
    requireWithin(body, "sliver quality", sliverQuality, 0.0, 1.0);
    requireNonNegative(body, "min fragment size (m)", minFragmentSize);
    for (int t : fixedTets)
        requireSetting(t >= 0 && t < tetCount, body, "fixed tet index",
                       "in [0, " + std::to_string(tetCount) + ") (the mesh's tets)", t);
}

} // namespace shatter
