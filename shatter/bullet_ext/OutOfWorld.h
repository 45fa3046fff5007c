#pragma once
// Changing a body in place that Bullet must not see change while it is in the world (its
// collision shape, its mass, its collision filter): the body leaves the world while `change`
// runs and comes back with the collision filter `change` leaves in `filter` (the one it had,
// unless changed). Bullet's contact pairs cache algorithms (and ours cache per-primitive ones)
// that point into the old shape; leaving the world drops them with their manifolds, and the
// broadphase box is recomputed on the way back.
#include <BulletDynamics/Dynamics/btDiscreteDynamicsWorld.h>
#include <BulletDynamics/Dynamics/btRigidBody.h>

namespace shatter {

struct CollisionFilter {
    int group = int(btBroadphaseProxy::DefaultFilter);
    int mask = int(btBroadphaseProxy::AllFilter);
};

template <class Change>
void outOfWorldWhile(btDiscreteDynamicsWorld& world, btRigidBody& body, const Change& change) {
    CollisionFilter filter;
    if (const btBroadphaseProxy* proxy = body.getBroadphaseHandle())
        filter = {proxy->m_collisionFilterGroup, proxy->m_collisionFilterMask};
    world.removeRigidBody(&body);
    change(filter);
    world.addRigidBody(&body, filter.group, filter.mask);
}

} // namespace shatter
