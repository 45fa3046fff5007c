#pragma once
// The contacts of one internal world step, read once. Shatter runs after Bullet has detected
// the contacts, solved them and integrated the bodies; the Plugin then copies every contact
// manifold (its points, the impulses the solver applied, the primitives touched) and the
// motion both bodies had at the end of the previous step. Every system reads this snapshot
// instead of walking the dispatcher's manifolds itself.
#include <BulletCollision/BroadphaseCollision/btDispatcher.h>
#include <BulletCollision/CollisionDispatch/btCollisionObject.h>
#include <BulletCollision/CollisionDispatch/btCollisionWorld.h>
#include <BulletDynamics/Dynamics/btRigidBody.h>

#include <span>
#include <unordered_map>
#include <vector>

namespace shatter {

// A body's rigid motion: velocity of its centre of mass, angular velocity, centre (world).
struct BodyMotion {
    btVector3 linear{0, 0, 0};
    btVector3 angular{0, 0, 0};
    btVector3 centre{0, 0, 0};

    btVector3 velocityAt(const btVector3& point) const { return linear + angular.cross(point - centre); }
};

struct ContactPoint {
    btVector3 onA, onB;   // the world points on each body
    btVector3 normalOnB;  // unit, from B toward A (Bullet's m_normalWorldOnB)
    btVector3 impulseOnA; // N·s the solver applied to A in this step, normal and friction (B got the opposite)
    btScalar distance;    // m, negative when the bodies overlap; up to Bullet's breaking threshold
    int primitiveA = -1;  // the group shape primitive touched on each side, or -1
    int primitiveB = -1;

    btVector3 midpoint() const { return btScalar(0.5) * (onA + onB); }
};

// One manifold: two bodies and their points.
struct ContactPair {
    const btCollisionObject* a = nullptr;
    const btCollisionObject* b = nullptr;
    btRigidBody* rigidA = nullptr; // a and b as rigid bodies, or null
    btRigidBody* rigidB = nullptr;
    BodyMotion beforeA, beforeB;   // each body's motion at the end of the previous step
    // At least one body was awake: the solver worked on the pair in this step. Points of a
    // pair of two sleeping (or static) bodies still hold the impulses of an earlier step.
    bool solved = false;
    // A system removed one of the bodies during this step: the pair is gone, as its manifold is.
    bool gone = false;
    btScalar processingThreshold = 0; // Bullet's contact processing threshold of the manifold
    int firstPoint = 0, pointCount = 0;

    bool involves(const btCollisionObject* o) const { return a == o || b == o; }
    const btCollisionObject* other(const btCollisionObject* self) const { return a == self ? b : a; }
    btRigidBody* rigid(const btCollisionObject* self) const { return a == self ? rigidA : rigidB; }
    const BodyMotion& before(const btCollisionObject* self) const { return a == self ? beforeA : beforeB; }
};

class ContactSnapshot {
public:
    // Copies the manifolds of this step. `before` holds the bodies' motion at the end of the
    // previous step (recordMotion); a body missing there (added since) counts with its motion now.
    void capture(btDispatcher& dispatcher);
    // The motion of every rigid body in `world` now, for the next step's `before`.
    void recordMotion(const btCollisionWorld& world);
    // Drops the recorded motions (no system needs them).
    void clearMotion() { motion_.clear(); }
    // A body left the world during the step: its pairs are gone.
    void forget(const btCollisionObject* object);

    const std::vector<ContactPair>& pairs() const { return pairs_; }
    std::span<const ContactPoint> points(const ContactPair& pair) const {
        return {points_.data() + pair.firstPoint, size_t(pair.pointCount)};
    }
    // Indices into pairs() of the pairs that involve `object`, in manifold order (an index
    // over all pairs is built on the first call of a step).
    std::span<const int> pairsOf(const btCollisionObject* object) const;

    // The impulse `self` received at a point (either side of the pair), and the point on it.
    static btVector3 impulseOn(const ContactPair& pair, const ContactPoint& p, const btCollisionObject* self) {
        return pair.a == self ? p.impulseOnA : -p.impulseOnA;
    }
    static const btVector3& pointOn(const ContactPair& pair, const ContactPoint& p, const btCollisionObject* self) {
        return pair.a == self ? p.onA : p.onB;
    }
    static int primitiveOn(const ContactPair& pair, const ContactPoint& p, const btCollisionObject* self) {
        return pair.a == self ? p.primitiveA : p.primitiveB;
    }
    // The unit normal at a point pointing from the other body into `self` (the push `self` gets).
    static btVector3 pushOn(const ContactPair& pair, const ContactPoint& p, const btCollisionObject* self) {
        return pair.a == self ? p.normalOnB : -p.normalOnB;
    }
    // How fast the two bodies approached each other along the normal at the point before the
    // step, m/s (positive: closing in).
    static double approachSpeed(const ContactPair& pair, const ContactPoint& p);

    // Adds to the impulse on A of point `index` (into the step's points: pair.firstPoint + k)
    // what a system applied there: for pairs that Bullet detected but did not solve (a soft
    // body's, whose points Bullet leaves at 0), which the system solved instead
    // (System::recordImpulses).
    void addImpulse(int index, const btVector3& impulseOnA);

    // Takes the point's impulse back from both bodies, about their centres where the solver
    // applied it (the pair's `before`; a body of zero inverse mass is not moved).
    static void undoImpulse(const ContactPair& pair, const ContactPoint& p);

private:
    BodyMotion motionBefore(const btCollisionObject* object) const;

    std::vector<ContactPair> pairs_;
    std::vector<ContactPoint> points_;
    std::vector<btPersistentManifold*> ordered_; // capture's scratch: the manifolds in order (OrderedContacts.h)
    mutable std::unordered_map<const btCollisionObject*, std::vector<int>> byObject_;
    mutable bool indexed_ = false;
    std::unordered_map<const btCollisionObject*, BodyMotion> motion_;
};

} // namespace shatter
