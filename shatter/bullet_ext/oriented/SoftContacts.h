#pragma once
// Bullet contacts of a soft body's primitives, as the oriented-particle solver's contact
// constraints (source 000 §3.2: collisions go through the world's own detection).
#include <shatter/bullet_ext/VisualBody.h>

#include <BulletCollision/CollisionDispatch/btCollisionWorld.h>
#include <vector>

namespace shatter {

// Contacts of the soft body's current shape with everything in the world (Bullet's
// contactTest), one per contact point: the particle of the touched primitive, the normal
// pointing into the soft body's side, the signed distance, and Bullet's friction product.
std::vector<oriented::ParticleContact> softContacts(btCollisionWorld& world, VisualBody& body);

} // namespace shatter
