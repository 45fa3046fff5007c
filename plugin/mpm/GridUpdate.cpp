#include "plugin/mpm/GridUpdate.h"

#include <cmath>

namespace shatter::mpm {

void updateGridVelocities(SimulationState& s, double dt) {
    Grid& g = s.grid;
    const long n = long(g.nodeCount());
    const double damping = std::exp(-s.scene.damping * dt);
#pragma omp parallel for schedule(static) num_threads(s.threads)
    for (long k = 0; k < n; ++k) {
        const size_t i = size_t(k);
        for (int f = 0; f < g.fields; ++f) {
            const double m = g.node[f][i].mass;
            Vec2& v = g.node[f][i].momentum; // becomes the velocity
            if (m <= 0 || g.fixedNode[i]) {
                v.setZero();
                continue;
            }
            v *= damping / m; // holds p + Δt·f (ParticleToGrid.h)
        }
    }
}

void collideGrid(SimulationState& s) {
    if (s.scene.colliders.empty()) return;
    Grid& g = s.grid;
    const long n = long(g.nodeCount());
#pragma omp parallel for schedule(static) num_threads(s.threads)
    for (long k = 0; k < n; ++k) {
        const size_t i = size_t(k);
        const Vec2 x = g.nodePosition(i);
        for (const auto& collider : s.scene.colliders) {
            if (collider->signedDistance(x) > 0) continue;
            for (int f = 0; f < g.fields; ++f)
                if (g.node[f][i].mass > 0) collider->project(x, g.node[f][i].momentum);
        }
    }
}

} // namespace shatter::mpm
