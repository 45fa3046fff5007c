#pragma once
// The background grid, rebuilt every substep over the particles' bounding box. Its origin is
// always a whole multiple of dx, so nodes sit at the same places from step to step.
// Each node holds up to three velocity fields (CRAMP, Nairn 2003): field 0 for particles on
// the node's side of every crack, field 1 for particles above a crack seen from the node,
// field 2 for particles below. Fields 1 and 2 exist only when the scene has cracks.
#include <shatter/plugin/mpm/Types.h>

#include <array>
#include <cstdint>
#include <vector>

namespace shatter::mpm {

struct Grid {
    static constexpr int maxFields = 3;

    double dx = 1, invDx = 1;
    Vec2 origin = Vec2::Zero();  // position of node (0, 0)
    int nx = 0, ny = 0;          // nodes per axis
    int fields = 1;              // 1 without cracks, 3 with

    // What one velocity field holds at one node; kept together because the transfers touch
    // all of it at once: four doubles, which the cubic transfers load and store as one
    // Double4 (ParticleToGrid.cpp, GridToParticle.cpp).
    struct Node {
        // The particles scatter momentum plus the substep's impulse, p + Δt·f (f: internal
        // and external force), in one sum: the update needs only (p + Δt f)/m. Becomes the
        // velocity after the grid update.
        Vec2 momentum = Vec2::Zero();
        double mass = 0;
        double unused = 0; // the fourth lane: stays zero, so that whole-node sums stay finite
    };
    static_assert(sizeof(Node) == 4 * sizeof(double), "a node is one Double4");
    // Per field, per node.
    std::array<std::vector<Node>, maxFields> node;
    std::array<std::vector<Vec2>, maxFields> displacement; // mass-weighted, for crack contact
    // Per node.
    std::vector<Vec2> crackNormal;       // sum of normals of crack segments seen from the node
    std::vector<std::uint8_t> fixedNode; // 1 when a fixed particle touches the node

    // A rectangle of node indices [i0, i1] x [j0, j1] (empty when i1 < i0).
    struct NodeRange {
        int i0 = 0, i1 = -1, j0 = 0, j1 = -1;
    };

    size_t nodeCount() const { return size_t(nx) * size_t(ny); }
    size_t index(int i, int j) const { return size_t(j) * size_t(nx) + size_t(i); }
    Vec2 nodePosition(int i, int j) const { return origin + dx * Vec2(i, j); }
    Vec2 nodePosition(size_t n) const { return nodePosition(int(n % size_t(nx)), int(n / size_t(nx))); }

    // Covers `bounds` plus `padCells` on every side, every array sized. Field 0 and the fixed
    // flags are not cleared (see clearField0); the crack data (fields 1 and 2, displacements,
    // crack normals) must be all zero before (see clearCrackData), and then stays so.
    // Throws std::runtime_error when the box would need more than `maxNodes` nodes
    // (particles that flew away), instead of exhausting memory.
    void resize(const Box& bounds, double cellSize, int padCells, int fieldCount, bool withCrackData,
                size_t maxNodes = 200'000'000);
    // Zeroes field 0 and the fixed flags of nodes [first, last) (the solver clears blocks of
    // nodes in parallel).
    void clearField0(size_t first, size_t last);
    // Zeroes the crack data of the nodes in `range`, outside which it is zero: only the
    // particles near a crack write it, and they reach only a small part of the grid.
    void clearCrackData(const NodeRange& range);
};

} // namespace shatter::mpm
