#include <shatter/bullet_ext/RemovalInWorld.h>

#include <BulletCollision/NarrowPhaseCollision/btPersistentManifold.h>

namespace shatter {

namespace {

// The point's primitive on the body's side after the removal (−1: removed). Points of a
// group's leaves name their primitive (part −1, index = primitive: LeafScope); others are left.
int renumbered(int part, int index, std::span<const int> to) {
    if (part != -1 || index < 0 || size_t(index) >= to.size()) return index;
    return to[size_t(index)];
}

} // namespace

void followRemoval(btDispatcher& dispatcher, const btCollisionObject& body, std::span<const int> to,
                   const btTransform& before) {
    const btTransform rebase = body.getWorldTransform().inverseTimes(before); // old body frame -> new
    // A body not reframed (a static piece) keeps its points as they are: its RᵀR in floats is not
    // exactly the identity, and each shrink would nudge them by a rounding step.
    const bool moved = !(before == body.getWorldTransform());
    for (int m = 0; m < dispatcher.getNumManifolds(); ++m) {
        btPersistentManifold* manifold = dispatcher.getManifoldByIndexInternal(m);
        const bool side0 = manifold->getBody0() == &body;
        if (!side0 && manifold->getBody1() != &body) continue;
        // Backwards: removeContactPoint moves the last point into the place it frees.
        for (int k = manifold->getNumContacts() - 1; k >= 0; --k) {
            btManifoldPoint& p = manifold->getContactPoint(k);
            int& index = side0 ? p.m_index0 : p.m_index1;
            const int now = renumbered(side0 ? p.m_partId0 : p.m_partId1, index, to);
            if (now < 0) {
                manifold->removeContactPoint(k);
                continue;
            }
            index = now;
            btVector3& local = side0 ? p.m_localPointA : p.m_localPointB;
            if (moved) local = rebase * local;
        }
    }
}

} // namespace shatter
