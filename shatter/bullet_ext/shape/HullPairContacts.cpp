#include <shatter/bullet_ext/shape/HullPairContacts.h>

#include <BulletCollision/CollisionShapes/btCollisionShape.h>

namespace shatter {

namespace {

btTransform relativeOf(const btManifoldResult& result) {
    return result.getBody0Wrap()->getWorldTransform().inverseTimes(result.getBody1Wrap()->getWorldTransform());
}

} // namespace

HullPairContacts& hullPairContacts() {
    static HullPairContacts settings;
    return settings;
}

bool keptWithoutClip(btPersistentManifold& manifold, btManifoldResult& result, const LastClip& last,
                     const HullPairContacts& settings) {
    if (settings.reclipAfter <= 0 || !last.valid || manifold.getNumContacts() < settings.minPoints) return false;
    // How far any point of body1's hull moved relative to body0 since the clip: the change of
    // the relative transform, its turn times the hull's reach from its origin.
    const btTransform change = last.relative.inverseTimes(relativeOf(result));
    const btScalar reach = result.getBody1Wrap()->getCollisionShape()->getAngularMotionDisc();
    const btScalar moved = change.getOrigin().length() + change.getRotation().getAngle() * reach;
    if (moved > btScalar(settings.reclipAfter) * manifold.getContactBreakingThreshold()) return false;
    result.refreshContactPoints();
    return manifold.getNumContacts() >= settings.minPoints;
}

void clipped(LastClip& last, const btManifoldResult& result) { clipped(last, relativeOf(result)); }

void clipped(LastClip& last, const btTransform& relative) {
    last.relative = relative;
    last.valid = true;
}

btPersistentManifold* soleManifold(btCollisionAlgorithm& algorithm) {
    thread_local btManifoldArray manifolds;
    manifolds.resize(0);
    algorithm.getAllContactManifolds(manifolds);
    return manifolds.size() == 1 ? manifolds[0] : nullptr;
}

} // namespace shatter
