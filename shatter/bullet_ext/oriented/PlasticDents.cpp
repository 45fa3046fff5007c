#include <shatter/bullet_ext/oriented/PlasticDents.h>

#include <shatter/bullet_ext/Convert.h>

#include <BulletCollision/NarrowPhaseCollision/btPersistentManifold.h>

namespace shatter {

void VelocitySnapshot::record(btCollisionWorld& world) {
    motion_.clear();
    const auto& objects = world.getCollisionObjectArray();
    for (int i = 0; i < objects.size(); ++i)
        if (const btRigidBody* body = btRigidBody::upcast(objects[i]))
            motion_[body] = {body->getLinearVelocity(), body->getAngularVelocity(), body->getCenterOfMassPosition()};
}

btVector3 VelocitySnapshot::velocityAt(const btCollisionObject& object, const btVector3& point) const {
    const auto it = motion_.find(&object);
    if (it != motion_.end()) return it->second.linear + it->second.angular.cross(point - it->second.centre);
    if (const btRigidBody* body = btRigidBody::upcast(&object)) return body->getVelocityInLocalPoint(point - body->getCenterOfMassPosition());
    return btVector3(0, 0, 0);
}

std::vector<oriented::Dent> findDents(btDispatcher& dispatcher, const VisualBody& body,
                                      const VelocitySnapshot& before, double dt) {
    std::vector<oriented::Dent> dents;
    const btCollisionObject* self = &body.rigidBody();
    const double threshold = body.settings().plastic.threshold;
    const btMatrix3x3 worldToMesh = body.meshTransform().getBasis().transpose();
    for (int m = 0; m < dispatcher.getNumManifolds(); ++m) {
        const btPersistentManifold& manifold = *dispatcher.getManifoldByIndexInternal(m);
        const bool first = manifold.getBody0() == self;
        if (!first && manifold.getBody1() != self) continue;
        const btCollisionObject& other = *(first ? manifold.getBody1() : manifold.getBody0());
        for (int k = 0; k < manifold.getNumContacts(); ++k) {
            const btManifoldPoint& point = manifold.getContactPoint(k);
            if (point.getDistance() > manifold.getContactProcessingThreshold()) continue;
            const int primitive = first ? point.m_index0 : point.m_index1;
            if (primitive < 0 || primitive >= body.shape().primitiveCount()) continue;
            // m_normalWorldOnB points from body 1 to body 0: the push the other body gives ours.
            const btVector3 push = first ? point.m_normalWorldOnB : -point.m_normalWorldOnB;
            const btVector3 at = 0.5 * (point.getPositionWorldOnA() + point.getPositionWorldOnB());
            const double approach = double((before.velocityAt(other, at) - before.velocityAt(*self, at)).dot(push));
            if (approach <= threshold) continue;
            dents.push_back({primitive, toEigen(worldToMesh * push) * (approach * dt)});
        }
    }
    return dents;
}

} // namespace shatter
