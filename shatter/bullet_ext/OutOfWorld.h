#pragma once
// Changing a body's collision shape in place: the body leaves the world while `change` runs and
// comes back with the same collision filter. Bullet's contact pairs cache algorithms (and ours
// cache per-primitive ones) that point into the old shape; leaving the world drops them, and the
// broadphase box is recomputed on the way back.
#include <BulletDynamics/Dynamics/btDiscreteDynamicsWorld.h>
#include <BulletDynamics/Dynamics/btRigidBody.h>

namespace shatter {

template <class Change>
void outOfWorldWhile(btDiscreteDynamicsWorld& world, btRigidBody& body, const Change& change) {
    const btBroadphaseProxy* proxy = body.getBroadphaseHandle();
    const int group = proxy ? proxy->m_collisionFilterGroup : int(btBroadphaseProxy::DefaultFilter);
    const int mask = proxy ? proxy->m_collisionFilterMask : int(btBroadphaseProxy::AllFilter);
    world.removeRigidBody(&body);
    change();
    world.addRigidBody(&body, group, mask);
}

} // namespace shatter
