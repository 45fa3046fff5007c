#pragma once
// Bullet contacts -> dents of plastic bodies (source 000 §3.5): a contact whose relative
// normal speed before the step exceeds the body's plastic threshold pushes the touched
// primitive in by that speed × the step.
#include <shatter/bullet_ext/VisualBody.h>

#include <BulletCollision/BroadphaseCollision/btDispatcher.h>
#include <BulletCollision/CollisionDispatch/btCollisionWorld.h>
#include <unordered_map>
#include <vector>

namespace shatter {

// The velocities every rigid body had at the end of the last step: Bullet's contact solve
// has already stopped the bodies when Shatter runs, so the speed of an impact is read from
// here. Bodies added since fall back to their current velocity.
class VelocitySnapshot {
public:
    void record(btCollisionWorld& world);
    // Velocity of the material point of `object` at `point` (world).
    btVector3 velocityAt(const btCollisionObject& object, const btVector3& point) const;

private:
    struct Motion {
        btVector3 linear, angular, centre;
    };
    std::unordered_map<const btCollisionObject*, Motion> motion_;
};

// Dents on `body` from this step's contact manifolds, offsets in mesh coordinates.
std::vector<oriented::Dent> findDents(btDispatcher& dispatcher, const VisualBody& body,
                                      const VelocitySnapshot& before, double dt);

} // namespace shatter
