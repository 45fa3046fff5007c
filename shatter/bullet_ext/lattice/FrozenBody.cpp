#include <shatter/bullet_ext/lattice/FrozenBody.h>

namespace shatter {

FrozenBody freezeBody(btDiscreteDynamicsWorld& world, btRigidBody& body) {
    FrozenBody frozen;
    frozen.mass = body.getMass();
    frozen.inertia = body.getLocalInertia();
    frozen.filterGroup = body.getBroadphaseHandle()->m_collisionFilterGroup;
    frozen.filterMask = body.getBroadphaseHandle()->m_collisionFilterMask;
    world.removeRigidBody(&body);
    body.setLinearVelocity(btVector3(0, 0, 0));
    body.setAngularVelocity(btVector3(0, 0, 0));
    body.setMassProps(0, btVector3(0, 0, 0)); // also sets CF_STATIC_OBJECT
    body.updateInertiaTensor();
    // As Bullet files its own static bodies: no pairs with other static ones (the ground, an
    // anchored wall, other frozen pieces). addRigidBody marks it ISLAND_SLEEPING.
    world.addRigidBody(&body, btBroadphaseProxy::StaticFilter,
                       frozen.filterMask & ~int(btBroadphaseProxy::StaticFilter));
    return frozen;
}

void thawBody(btDiscreteDynamicsWorld& world, btRigidBody& body, const FrozenBody& frozen) {
    world.removeRigidBody(&body);
    body.setMassProps(frozen.mass, frozen.inertia); // also clears CF_STATIC_OBJECT
    body.updateInertiaTensor();
    world.addRigidBody(&body, frozen.filterGroup, frozen.filterMask); // sets the world's gravity
    body.forceActivationState(ACTIVE_TAG);
    body.setDeactivationTime(0);
}

} // namespace shatter
