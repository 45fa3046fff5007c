#include "plugin/mpm/GridUpdate.h"

#include "plugin/mpm/CrackContact.h"

#include <cmath>

namespace shatter::mpm {

namespace {

// Returns false when no field of the node holds mass (the later stages skip it).
bool nodeVelocities(Grid& g, size_t i, double damping) {
    bool any = false;
    for (int f = 0; f < g.fields; ++f) {
        const double m = g.node[f][i].mass;
        Vec2& v = g.node[f][i].momentum; // becomes the velocity
        if (m <= 0 || g.fixedNode[i]) {
            v.setZero();
            any = any || m > 0;
            continue;
        }
        v *= damping / m; // holds p + Δt·f (ParticleToGrid.h)
        any = true;
    }
    return any;
}

void collideNode(Grid& g, const std::vector<std::shared_ptr<const Collider>>& colliders, size_t i) {
    const Vec2 x = g.nodePosition(i);
    for (const auto& collider : colliders) {
        if (collider->signedDistance(x) > 0) continue;
        for (int f = 0; f < g.fields; ++f)
            if (g.node[f][i].mass > 0) collider->project(x, g.node[f][i].momentum);
    }
}

} // namespace

void updateGrid(SimulationState& s, double dt) {
    Grid& g = s.grid;
    const long n = long(g.nodeCount());
    const double damping = std::exp(-s.scene.damping * dt);
    const bool contact = s.hasCracks(), collide = !s.scene.colliders.empty();
#pragma omp parallel for schedule(static) num_threads(s.threads)
    for (long k = 0; k < n; ++k) {
        const size_t i = size_t(k);
        if (!nodeVelocities(g, i, damping)) continue; // empty: zero velocity, nothing to collide
        if (contact) crackContactAtNode(g, i);
        if (collide) collideNode(g, s.scene.colliders, i);
        if (contact) crackContactAtNode(g, i);
    }
}

} // namespace shatter::mpm
