#include <shatter/plugin/mpm/GridUpdate.h>

#include <shatter/plugin/mpm/CrackContact.h>

#include <cmath>
#include <cstdint>

namespace shatter::mpm {

namespace {

// Returns false when no field of the node holds mass (the later stages skip it). Only the
// first `fields` fields are looked at (the others are empty there).
bool nodeVelocities(Grid& g, size_t i, double damping, int fields) {
    bool any = false;
    for (int f = 0; f < fields; ++f) {
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

// `near`: which colliders may touch the node (collidersTouching).
void collideNode(Grid& g, const ColliderList& colliders, std::uint64_t near, size_t i) {
    const Vec2 x = g.nodePosition(i);
    for (size_t k = 0; k < colliders.size(); ++k) {
        if (!mustTest(near, k)) continue;
        if (colliders[k]->signedDistance(x) > 0) continue;
        for (int f = 0; f < g.fields; ++f)
            if (g.node[f][i].mass > 0) colliders[k]->project(x, g.node[f][i].momentum);
    }
}

// The colliders that may touch a node of row j: the row's box grown by half a cell, so that
// rounding never hides a touching node.
std::uint64_t collidersNearRow(const Grid& g, const ColliderList& colliders, int j) {
    const Vec2 margin = Vec2::Constant(0.5 * g.dx);
    return collidersTouching(colliders, Box{g.nodePosition(0, j) - margin, g.nodePosition(g.nx - 1, j) + margin});
}

} // namespace

void updateGrid(SimulationState& s, double dt) {
    Grid& g = s.grid;
    const double damping = std::exp(-s.scene.damping * dt);
    const auto& colliders = s.scene.colliders;
    // Fields 1 and 2 and the crack data are zero outside these nodes (FieldAssignment.h): the
    // other nodes have one field and no crack contact.
    const Grid::NodeRange crack = s.hasCracks() ? s.fields.nodes : Grid::NodeRange{};
#pragma omp parallel for schedule(static) num_threads(s.threads)
    for (int j = 0; j < g.ny; ++j) {
        const std::uint64_t near = collidersNearRow(g, colliders, j);
        const bool anyCollider = anyToTest(near, colliders);
        const bool crackRow = j >= crack.j0 && j <= crack.j1;
        for (int i = 0; i < g.nx; ++i) {
            const size_t n = g.index(i, j);
            const bool crackNode = crackRow && i >= crack.i0 && i <= crack.i1;
            if (!nodeVelocities(g, n, damping, crackNode ? g.fields : 1)) continue; // empty: nothing to collide
            if (crackNode) crackContactAtNode(g, n);
            if (anyCollider) collideNode(g, colliders, near, n);
            if (crackNode) crackContactAtNode(g, n);
        }
    }
}

} // namespace shatter::mpm
