#include <shatter/bullet_ext/OrderedContacts.h>

#include <shatter/bullet_ext/AttachedWorld.h>

#include <BulletCollision/BroadphaseCollision/btBroadphaseProxy.h>
#include <BulletCollision/CollisionDispatch/btCollisionObject.h>
#include <BulletCollision/NarrowPhaseCollision/btPersistentManifold.h>
#include <algorithm>
#include <array>

namespace shatter {

namespace {

std::array<int, 6> orderKey(const btPersistentManifold* m) {
    const btManifoldPoint& p = m->getContactPoint(0);
    return {m->getBody0()->getBroadphaseHandle()->m_uniqueId, m->getBody1()->getBroadphaseHandle()->m_uniqueId,
            p.m_partId0, p.m_index0, p.m_partId1, p.m_index1};
}

} // namespace

bool contactPairBefore(const btPersistentManifold* a, const btPersistentManifold* b) { return orderKey(a) < orderKey(b); }

void orderContactManifolds(btPersistentManifold* const* manifolds, int count, std::vector<btPersistentManifold*>& ordered) {
    ordered.clear();
    for (int m = 0; m < count; ++m)
        if (manifolds[m]->getNumContacts() > 0) ordered.push_back(manifolds[m]);
    std::stable_sort(ordered.begin(), ordered.end(), contactPairBefore);
}

btScalar OrderedContactSolver::solveGroup(btCollisionObject** bodies, int numBodies, btPersistentManifold** manifolds,
                                          int numManifolds, btTypedConstraint** constraints, int numConstraints,
                                          const btContactSolverInfo& info, btIDebugDraw* debugDrawer,
                                          btDispatcher* dispatcher) {
    if (!dispatcherOrdersContacts(dispatcher))
        return inner_->solveGroup(bodies, numBodies, manifolds, numManifolds, constraints, numConstraints, info,
                                  debugDrawer, dispatcher);
    // Per thread: a multi-threaded world solves islands on several threads at once.
    thread_local std::vector<btPersistentManifold*> ordered; // reused: no allocation once warm
    orderContactManifolds(manifolds, numManifolds, ordered);
    return inner_->solveGroup(bodies, numBodies, ordered.data(), int(ordered.size()), constraints, numConstraints, info,
                              debugDrawer, dispatcher);
}

} // namespace shatter
