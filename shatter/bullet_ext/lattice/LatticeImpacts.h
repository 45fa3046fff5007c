#pragma once
// Impacts on lattice bodies from Bullet's contact manifolds: the impulse each contact point
// applied in the step just solved (normal and friction), where, and to which bodies.
#include <BulletCollision/CollisionDispatch/btCollisionObject.h>
#include <BulletCollision/BroadphaseCollision/btDispatcher.h>
#include <shatter/plugin/lattice/NearestParticles.h>

#include <Eigen/Core>

#include <unordered_map>
#include <vector>

class btRigidBody;

namespace shatter {

struct ContactImpulse {
    btRigidBody* bodyA = nullptr;   // the manifold's two bodies (either may be static)
    btRigidBody* bodyB = nullptr;
    Eigen::Vector3d onA;            // impulse on A, N·s (B got the opposite)
    Eigen::Vector3d pointA, pointB; // world contact points on each body
    int primitiveA = -1, primitiveB = -1; // the group shape primitive touched on each side, or -1
};

// Every contact point with a non-zero impulse, in the dispatcher's manifold order, whose
// manifold involves one of `watched`. Deterministic for a deterministic world.
std::vector<ContactImpulse> collectContactImpulses(btDispatcher& dispatcher,
                                                   const std::unordered_map<const btCollisionObject*, int>& watched);

// The impulse `body` received from the contact and where.
inline Eigen::Vector3d impulseOn(const ContactImpulse& c, const btRigidBody* body) {
    return c.bodyA == body ? c.onA : Eigen::Vector3d(-c.onA);
}
inline const Eigen::Vector3d& pointOn(const ContactImpulse& c, const btRigidBody* body) {
    return c.bodyA == body ? c.pointA : c.pointB;
}
inline int primitiveOn(const ContactImpulse& c, const btRigidBody* body) {
    return c.bodyA == body ? c.primitiveA : c.primitiveB;
}

// Takes the contact's impulse back from both bodies (nothing happens to a static one).
void undoContactImpulse(const ContactImpulse& c);

// Spreads a force at `point` over `nearest` (squared distances and particle indices, nearest
// first) with inverse-distance weights summing to one, and adds it to `loads` (3 per particle).
void addPointForce(const std::vector<std::pair<double, int>>& nearest, const Eigen::Vector3d& force,
                   Eigen::VectorXd& loads);

} // namespace shatter
