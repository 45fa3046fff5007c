#include <shatter/bullet_ext/lattice/FrozenBody.h>

namespace shatter {

FrozenBody freezeBody(btRigidBody& body, CollisionFilter& filter) {
    FrozenBody frozen{body.getMass(), body.getLocalInertia(), filter};
    body.setLinearVelocity(btVector3(0, 0, 0));
    body.setAngularVelocity(btVector3(0, 0, 0));
    body.setMassProps(0, btVector3(0, 0, 0)); // also sets CF_STATIC_OBJECT
    body.updateInertiaTensor();
    // As Bullet files its own static bodies: no pairs with other static ones (the ground, an
    // anchored wall, other frozen pieces). A debris piece stays debris (no pairs with other
    // debris, which leave it out of their masks). addRigidBody marks it ISLAND_SLEEPING.
    const int debris = filter.group & int(btBroadphaseProxy::DebrisFilter);
    filter = {int(btBroadphaseProxy::StaticFilter) | debris, filter.mask & ~int(btBroadphaseProxy::StaticFilter)};
    return frozen;
}

void thawBody(btRigidBody& body, const FrozenBody& frozen, CollisionFilter& filter) {
    body.setMassProps(frozen.mass, frozen.inertia); // also clears CF_STATIC_OBJECT
    body.updateInertiaTensor();
    filter = frozen.filter; // addRigidBody sets the world's gravity
}

} // namespace shatter
