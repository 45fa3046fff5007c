#include <shatter/bullet_ext/lattice/LatticeImpacts.h>

#include <shatter/bullet_ext/Convert.h>

#include <BulletCollision/NarrowPhaseCollision/btPersistentManifold.h>
#include <BulletDynamics/Dynamics/btRigidBody.h>

#include <algorithm>
#include <cmath>

namespace shatter {

std::vector<ContactImpulse> collectContactImpulses(btDispatcher& dispatcher,
                                                   const std::unordered_map<const btCollisionObject*, int>& watched) {
    std::vector<ContactImpulse> out;
    const int count = dispatcher.getNumManifolds();
    for (int m = 0; m < count; ++m) {
        const btPersistentManifold* manifold = dispatcher.getManifoldByIndexInternal(m);
        if (manifold->getNumContacts() == 0) continue;
        // Two bodies asleep (or static): the solver did not touch the pair this step, and its
        // points still hold the impulses of the step they fell asleep in.
        if (!manifold->getBody0()->isActive() && !manifold->getBody1()->isActive()) continue;
        if (!watched.count(manifold->getBody0()) && !watched.count(manifold->getBody1())) continue;
        auto* a = const_cast<btRigidBody*>(btRigidBody::upcast(manifold->getBody0()));
        auto* b = const_cast<btRigidBody*>(btRigidBody::upcast(manifold->getBody1()));
        if (!a || !b) continue;
        for (int p = 0; p < manifold->getNumContacts(); ++p) {
            const btManifoldPoint& pt = manifold->getContactPoint(p);
            // The solver pushes A along the normal on B and pulls it along each friction
            // direction by the stored impulses (B gets the opposite).
            const btVector3 j = pt.m_normalWorldOnB * pt.m_appliedImpulse +
                                pt.m_lateralFrictionDir1 * pt.m_appliedImpulseLateral1 +
                                pt.m_lateralFrictionDir2 * pt.m_appliedImpulseLateral2;
            if (j.isZero()) continue;
            // The group shape's algorithms name the primitive as (partId -1, index).
            out.push_back({a, b, toEigen(j), toEigen(pt.getPositionWorldOnA()), toEigen(pt.getPositionWorldOnB()),
                           pt.m_partId0 == -1 ? pt.m_index0 : -1, pt.m_partId1 == -1 ? pt.m_index1 : -1});
        }
    }
    return out;
}

void undoContactImpulse(const ContactImpulse& c) {
    // applyImpulse ignores bodies of zero inverse mass (static, kinematic).
    c.bodyA->applyImpulse(toBullet(Eigen::Vector3d(-c.onA)), toBullet(c.pointA) - c.bodyA->getCenterOfMassPosition());
    c.bodyB->applyImpulse(toBullet(c.onA), toBullet(c.pointB) - c.bodyB->getCenterOfMassPosition());
}

void addPointForce(const std::vector<std::pair<double, int>>& nearest, const Eigen::Vector3d& force,
                   Eigen::VectorXd& loads) {
    const int k = int(nearest.size());
    if (k <= 0) return;
    // Inverse distance, softened by a thousandth of the farthest of the k so a contact right
    // on a centroid does not divide by zero.
    const double soft = 1e-3 * std::sqrt(nearest[k - 1].first) + 1e-12;
    double total = 0.0;
    for (int j = 0; j < k; ++j) total += 1.0 / (std::sqrt(nearest[j].first) + soft);
    for (int j = 0; j < k; ++j) {
        const double w = 1.0 / (std::sqrt(nearest[j].first) + soft) / total;
        loads.segment<3>(3 * nearest[j].second) += w * force;
    }
}

} // namespace shatter
