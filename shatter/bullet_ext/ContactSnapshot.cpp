#include <shatter/bullet_ext/ContactSnapshot.h>

#include <shatter/bullet_ext/AttachedWorld.h>
#include <shatter/bullet_ext/OrderedContacts.h>

#include <BulletCollision/NarrowPhaseCollision/btPersistentManifold.h>
#include <stdexcept>
#include <string>

namespace shatter {

namespace {

BodyMotion motionNow(const btCollisionObject* object) {
    const btRigidBody* body = btRigidBody::upcast(object);
    if (!body) return {btVector3(0, 0, 0), btVector3(0, 0, 0), object->getWorldTransform().getOrigin()};
    return {body->getLinearVelocity(), body->getAngularVelocity(), body->getCenterOfMassPosition()};
}

} // namespace

BodyMotion ContactSnapshot::motionBefore(const btCollisionObject* object) const {
    const auto it = motion_.find(object);
    return it != motion_.end() ? it->second : motionNow(object);
}

void ContactSnapshot::capture(btDispatcher& dispatcher) {
    pairs_.clear();
    points_.clear();
    byObject_.clear();
    indexed_ = false;
    // The pairs in the solver's order when that is the manifolds' own (OrderedContacts.h): the
    // systems' sums over them then do not depend on the manifolds' places either.
    const bool ordered = dispatcherOrdersContacts(&dispatcher);
    if (ordered) orderContactManifolds(dispatcher.getInternalManifoldPointer(), dispatcher.getNumManifolds(), ordered_);
    const int count = ordered ? int(ordered_.size()) : dispatcher.getNumManifolds();
    for (int m = 0; m < count; ++m) {
        const btPersistentManifold& manifold = ordered ? *ordered_[m] : *dispatcher.getManifoldByIndexInternal(m);
        if (manifold.getNumContacts() == 0) continue;
        ContactPair pair;
        pair.a = manifold.getBody0();
        pair.b = manifold.getBody1();
        pair.rigidA = const_cast<btRigidBody*>(btRigidBody::upcast(pair.a));
        pair.rigidB = const_cast<btRigidBody*>(btRigidBody::upcast(pair.b));
        pair.beforeA = motionBefore(pair.a);
        pair.beforeB = motionBefore(pair.b);
        pair.solved = pair.a->isActive() || pair.b->isActive();
        pair.processingThreshold = manifold.getContactProcessingThreshold();
        pair.firstPoint = int(points_.size());
        pair.pointCount = manifold.getNumContacts();
        for (int k = 0; k < manifold.getNumContacts(); ++k) {
            const btManifoldPoint& pt = manifold.getContactPoint(k);
            ContactPoint p;
            p.onA = pt.getPositionWorldOnA();
            p.onB = pt.getPositionWorldOnB();
            p.normalOnB = pt.m_normalWorldOnB;
            // The solver pushes A along the normal on B and pulls it along each friction
            // direction by the stored impulses (B gets the opposite).
            p.impulseOnA = pt.m_normalWorldOnB * pt.m_appliedImpulse + pt.m_lateralFrictionDir1 * pt.m_appliedImpulseLateral1 +
                           pt.m_lateralFrictionDir2 * pt.m_appliedImpulseLateral2;
            p.distance = pt.getDistance();
            // The group shape's algorithms name the primitive as (partId -1, index).
            p.primitiveA = pt.m_partId0 == -1 ? pt.m_index0 : -1;
            p.primitiveB = pt.m_partId1 == -1 ? pt.m_index1 : -1;
            points_.push_back(p);
        }
        pairs_.push_back(pair);
    }
}

void ContactSnapshot::recordMotion(const btCollisionWorld& world) {
    motion_.clear();
    const auto& objects = world.getCollisionObjectArray();
    for (int i = 0; i < objects.size(); ++i)
        if (btRigidBody::upcast(objects[i])) motion_[objects[i]] = motionNow(objects[i]);
}

void ContactSnapshot::forget(const btCollisionObject* object) {
    for (ContactPair& pair : pairs_)
        if (pair.involves(object)) pair.gone = true;
    motion_.erase(object);
}

std::span<const int> ContactSnapshot::pairsOf(const btCollisionObject* object) const {
    if (!indexed_) {
        for (int i = 0; i < int(pairs_.size()); ++i) {
            byObject_[pairs_[i].a].push_back(i);
            byObject_[pairs_[i].b].push_back(i);
        }
        indexed_ = true;
    }
    const auto it = byObject_.find(object);
    if (it == byObject_.end()) return {};
    return it->second;
}

double ContactSnapshot::approachSpeed(const ContactPair& pair, const ContactPoint& p) {
    const btVector3 at = p.midpoint();
    // Body B approaches A along the normal (which points from B toward A).
    return double((pair.beforeB.velocityAt(at) - pair.beforeA.velocityAt(at)).dot(p.normalOnB));
}

void ContactSnapshot::undoImpulse(const ContactPair& pair, const ContactPoint& p) {
    // applyImpulse ignores bodies of zero inverse mass (static, kinematic).
    // About each body's centre where the solver applied the impulse: the step has moved it on
    // since (by v·dt: 4 cm for a ball at 10 m/s in a 1/240 s step, which against the ball's
    // 800 N·s of stopping impulse would leave it 70 rad/s of spin that it never had).
    if (pair.rigidA) pair.rigidA->applyImpulse(-p.impulseOnA, p.onA - pair.beforeA.centre);
    if (pair.rigidB) pair.rigidB->applyImpulse(p.impulseOnA, p.onB - pair.beforeB.centre);
}

void ContactSnapshot::addImpulse(int index, const btVector3& impulseOnA) {
    if (index < 0 || size_t(index) >= points_.size())
        throw std::out_of_range("ContactSnapshot::addImpulse: no point " + std::to_string(index) + " in this step's " +
                                std::to_string(points_.size()));
    points_[size_t(index)].impulseOnA += impulseOnA;
}

} // namespace shatter
