#include <shatter/bullet_ext/lattice/FrozenBody.h>

namespace shatter {

FrozenBody freezeBody(btRigidBody& body, CollisionFilter& filter) {
    FrozenBody frozen{body.getMass(), body.getLocalInertia(), filter};
    body.setLinearVelocity(btVector3(0, 0, 0));
    body.setAngularVelocity(btVector3(0, 0, 0));
    body.setMassProps(0, btVector3(0, 0, 0)); // also sets CF_STATIC_OBJECT
    body.updateInertiaTensor();
    // As Bullet files its own static bodies: no pairs with other static ones (the ground, an
    // anchored wall, other frozen pieces). addRigidBody marks it ISLAND_SLEEPING.
    filter = {int(btBroadphaseProxy::StaticFilter), filter.mask & ~int(btBroadphaseProxy::StaticFilter)};
    return frozen;
}

void thawBody(btRigidBody& body, const FrozenBody& frozen, CollisionFilter& filter) {
    body.setMassProps(frozen.mass, frozen.inertia); // also clears CF_STATIC_OBJECT
    body.updateInertiaTensor();
    filter = frozen.filter; // addRigidBody sets the world's gravity
}

} // namespace shatter
