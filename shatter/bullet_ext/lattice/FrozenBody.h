#pragma once
// Freezing a resting dynamic body: it becomes a static body (mass 0, Bullet's static collision
// filter) so that it leaves Bullet's simulation islands and its pairs with static bodies, and
// thawing makes it the same dynamic body again. Bullet puts a body to sleep only with its whole
// island, and an island is every body whose box overlaps another's, transitively: in a heap of
// fragments a few pieces that still move keep all of them awake, and the narrowphase over the
// heap's box pairs then costs most of a frame. Frozen pieces cost nothing.
// Both run while the body is out of the world (SystemContext::reshape), which hands them the
// collision filter the body comes back with.
#include <shatter/bullet_ext/OutOfWorld.h>

#include <BulletDynamics/Dynamics/btRigidBody.h>

namespace shatter {

// What a thaw needs to restore (the body's own values when it was frozen).
struct FrozenBody {
    btScalar mass = 0;
    btVector3 inertia{0, 0, 0}; // principal moments, body frame
    CollisionFilter filter;
};

// Makes the (dynamic) body static and at rest, filed as Bullet files its own static bodies.
FrozenBody freezeBody(btRigidBody& body, CollisionFilter& filter);

// Makes the body what it was before freezeBody, at rest; it must be woken once back in the world.
void thawBody(btRigidBody& body, const FrozenBody& frozen, CollisionFilter& filter);

} // namespace shatter
