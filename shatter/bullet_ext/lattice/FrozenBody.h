#pragma once
// Freezing a resting dynamic body: it becomes a static body (mass 0, Bullet's static collision
// filter) so that it leaves Bullet's simulation islands and its pairs with static bodies, and
// thawing makes it the same dynamic body again. Bullet puts a body to sleep only with its whole
// island, and an island is every body whose box overlaps another's, transitively: in a heap of
// fragments a few pieces that still move keep all of them awake, and the narrowphase over the
// heap's box pairs then costs most of a frame. Frozen pieces cost nothing.
#include <BulletDynamics/Dynamics/btDiscreteDynamicsWorld.h>
#include <BulletDynamics/Dynamics/btRigidBody.h>

namespace shatter {

// What a thaw needs to restore (the body's own values when it was frozen).
struct FrozenBody {
    btScalar mass = 0;
    btVector3 inertia{0, 0, 0}; // principal moments, body frame
    int filterGroup = 0;
    int filterMask = 0;
};

// Takes `body` (dynamic, in `world`) out of the world and puts it back as a static body at rest.
FrozenBody freezeBody(btDiscreteDynamicsWorld& world, btRigidBody& body);

// Puts the body back as it was before freezeBody, at rest and awake.
void thawBody(btDiscreteDynamicsWorld& world, btRigidBody& body, const FrozenBody& frozen);

} // namespace shatter
