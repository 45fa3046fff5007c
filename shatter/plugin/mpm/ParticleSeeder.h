#pragma once
// Fills the scene's bodies with particles on one global lattice of spacing dx/ppc, points at
// ((i + ½)h, (j + ½)h). A lattice shared by all bodies means bodies that touch tile without
// gaps or overlaps; where bodies overlap, the one listed later takes the site (so an
// inclusion is a body listed after its host).
#include <shatter/plugin/mpm/Particles.h>
#include <shatter/plugin/mpm/Scene.h>

#include <cstdint>
#include <map>
#include <utility>
#include <vector>

namespace shatter::mpm {

struct SeededParticles {
    // Ordered column by column (lattice i, then j): the particles of one vertical stripe of
    // the scatter (StripeOrder) are then mostly consecutive in memory.
    Particles particles;
    std::vector<std::uint8_t> surface; // 1: a lattice neighbour is empty (outer layer)
    double spacing = 0;                // h = dx/ppc, m
    std::map<std::pair<long, long>, std::uint32_t> lattice; // (i, j) → particle

    // The surface particle nearest to p within `radius`, or −1.
    long nearestSurface(const Vec2& p, double radius) const;
};

// Throws shatter::InputError when a body holds no lattice point (smaller than the spacing).
SeededParticles seedParticles(const Scene& scene);

} // namespace shatter::mpm
