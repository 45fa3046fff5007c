#include <shatter/bullet_ext/shape/HullPairContacts.h>

#include <BulletCollision/CollisionShapes/btConvexShape.h>
#include <BulletCollision/NarrowPhaseCollision/btGjkEpaPenetrationDepthSolver.h>
#include <BulletCollision/NarrowPhaseCollision/btGjkPairDetector.h>
#include <BulletCollision/NarrowPhaseCollision/btVoronoiSimplexSolver.h>

namespace shatter {

namespace {

// GJK measures the margin-grown shapes; the clip measures the hulls themselves. This result
// turns the first into the second (distance + both margins, the point moved from B's grown
// surface onto B's hull) before it reaches the manifold, so kept and clipped points agree
// on where a pair rests.
class CorePoint : public btDiscreteCollisionDetectorInterface::Result {
public:
    CorePoint(btManifoldResult& out, btScalar marginA, btScalar marginB, btScalar threshold)
        : out_(out), marginA_(marginA), marginB_(marginB), threshold_(threshold) {}
    void setShapeIdentifiersA(int, int) override {}
    void setShapeIdentifiersB(int, int) override {}
    void addContactPoint(const btVector3& normalOnB, const btVector3& pointOnB, btScalar depth) override {
        const btScalar distance = depth + marginA_ + marginB_;
        if (distance < threshold_) out_.addContactPoint(normalOnB, pointOnB - normalOnB * marginB_, distance);
    }

private:
    btManifoldResult& out_;
    btScalar marginA_, marginB_, threshold_;
};

} // namespace

HullPairContacts& hullPairContacts() {
    static HullPairContacts settings;
    return settings;
}

btPersistentManifold* soleManifold(btCollisionAlgorithm& algorithm) {
    thread_local btManifoldArray manifolds;
    manifolds.resize(0);
    algorithm.getAllContactManifolds(manifolds);
    return manifolds.size() == 1 ? manifolds[0] : nullptr;
}

bool keptByGjk(btPersistentManifold* manifold, btManifoldResult* result, const HullPairContacts& settings) {
    if (settings.clipBelowPoints <= 0 || !manifold || manifold->getNumContacts() < settings.clipBelowPoints) return false;
    result->refreshContactPoints();
    if (manifold->getNumContacts() < settings.clipBelowPoints) return false;

    // In the result's own order, so the normal GJK reports is on the result's body1.
    const btCollisionObjectWrapper* a = result->getBody0Wrap();
    const btCollisionObjectWrapper* b = result->getBody1Wrap();
    const auto* shapeA = static_cast<const btConvexShape*>(a->getCollisionShape());
    const auto* shapeB = static_cast<const btConvexShape*>(b->getCollisionShape());
    const btScalar threshold = manifold->getContactBreakingThreshold() + result->m_closestPointDistanceThreshold;
    btVoronoiSimplexSolver simplex;
    btGjkEpaPenetrationDepthSolver epa;
    btGjkPairDetector gjk(shapeA, shapeB, &simplex, &epa);
    btGjkPairDetector::ClosestPointInput input;
    input.m_transformA = a->getWorldTransform();
    input.m_transformB = b->getWorldTransform();
    const btScalar reach = shapeA->getMargin() + shapeB->getMargin() + threshold;
    input.m_maximumDistanceSquared = reach * reach;
    CorePoint core(*result, shapeA->getMargin(), shapeB->getMargin(), threshold);
    gjk.getClosestPoints(input, core, nullptr);
    result->refreshContactPoints();
    return true;
}

} // namespace shatter
