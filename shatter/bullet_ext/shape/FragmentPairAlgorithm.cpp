#include <shatter/bullet_ext/shape/FragmentPairAlgorithm.h>

#include <shatter/bullet_ext/shape/AxisLanes.h>
#include <shatter/bullet_ext/shape/FragmentHull.h>
#include <shatter/bullet_ext/shape/HullLanes.h>
#include <shatter/bullet_ext/shape/HullPairContacts.h>
#include <shatter/bullet_ext/shape/PolyhedronContacts.h>

#include <BulletCollision/CollisionDispatch/btCollisionConfiguration.h>
#include <BulletCollision/CollisionDispatch/btCollisionObjectWrapper.h>
#include <BulletCollision/CollisionShapes/btConvexPolyhedron.h>
#include <BulletCollision/NarrowPhaseCollision/btPersistentManifold.h>
#include <LinearMath/btAabbUtil2.h>

#include <bit>
#include <new>

namespace shatter {

namespace {

btCollisionAlgorithmCreateFunc* configurationHullHull(btDispatcher* dispatcher) {
    return static_cast<btCollisionDispatcher*>(dispatcher)
        ->getCollisionConfiguration()
        ->getCollisionAlgorithmCreateFunc(CONVEX_HULL_SHAPE_PROXYTYPE, CONVEX_HULL_SHAPE_PROXYTYPE);
}

// The first face f of `planes` (`hint` tried first) for which separates(f); -1 when none.
template <typename Separates>
int firstSeparating(const btConvexPolyhedron& planes, int hint, const Separates& separates) {
    if (hint >= 0 && separates(hint)) return hint;
    for (int f = 0; f < planes.m_faces.size(); ++f)
        if (f != hint && separates(f)) return f;
    return -1;
}

// Lanes whose comparison holds, one bit a lane.
int laneBits(const Float4& a, const Float4& b) {
    const auto greater = a > b;
    return (greater[0] & 1) | (greater[1] & 2) | (greater[2] & 4) | (greater[3] & 8);
}

// separatingFaceOf for two hulls that keep their lanes (a group's leaf hulls, HullLanes.h):
// `other`'s vertices mapped four at a time (placed: toPlanes * v's bits), the hint's face tried
// as below, then every face four at a time, each lane's least projection (vertex · normal, as
// VertexLanes::extentAlong takes it) plus its plane's offset against the gap. A least of equal
// projections may be the other zero, which changes no comparison of its sum; so each face
// separates exactly when it does below, and the first one after the hint is the same.
int separatingFaceInLanes(const HullLanes& planes, int faces, const HullLanes& other, const btTransform& toPlanes,
                          btScalar gap, int hint) {
    Vector4 mapped[HullLanes::kMaxVertices / 4];
    for (int k = 0; k < other.vertexBlocks; ++k) mapped[k] = placed(toPlanes, other.vertices[k]);
    const Float4 gaps = Float4{} + gap;
    if (hint >= 0) {
        const Vector4& block = planes.faceNormals[hint / 4];
        const Vector4 normal = splat(btVector3(block.x[hint % 4], block.y[hint % 4], block.z[hint % 4]));
        Float4 low = dot(mapped[0], normal);
        for (int k = 1; k < other.vertexBlocks; ++k) {
            const Float4 p = dot(mapped[k], normal);
            low = p < low ? p : low;
        }
        if (lowest(low) + planes.faceOffsets[hint / 4][hint % 4] > gap) return hint;
    }
    int apart = 0;
    for (int b = 0; b < planes.faceBlocks; ++b) {
        Float4 low, high; // only the least is read (inlined, the greatest is never computed)
        extentAlongAxes(planes.faceNormals[b], mapped, other.vertexBlocks, low, high);
        apart |= laneBits(low + planes.faceOffsets[b], gaps) << (4 * b);
    }
    apart &= ((1 << faces) - 1) & ~(hint >= 0 ? 1 << hint : 0);
    return apart != 0 ? std::countr_zero(unsigned(apart)) : -1;
}

// A face of `planes` (in its own frame) with every vertex of `other` (mapped into that frame
// by `toPlanes`) in front by more than `gap`, `hint` tried first; -1 when none. The vertices
// are mapped once (they were mapped again for every face: a fifth of the narrowphase in the
// wall's heap).
int separatingFaceOf(const btConvexPolyhedron& planes, const btConvexPolyhedron& other, const btTransform& toPlanes,
                     btScalar gap, int hint) {
    const HullLanes* planeLanes = keptLanes(planes);
    const HullLanes* otherLanes = keptLanes(other);
    if (planeLanes && otherLanes && planeLanes->faceBlocks > 0 && otherLanes->vertexBlocks > 0)
        return separatingFaceInLanes(*planeLanes, planes.m_faces.size(), *otherLanes, toPlanes, gap, hint);
    if (other.m_vertices.size() <= VertexLanes::kMaxVertices) {
        // A small hull (a tet): its vertices mapped and projected on each face's normal all at
        // once (VertexLanes: btVector3::dot's bits per lane). The nearest vertex's distance is
        // the least projection plus the plane's offset (adding a constant keeps the order of
        // floats), so each face gives the answer the vertex-by-vertex loop below gives.
        VertexLanes mapped;
        mapped.assign(other.m_vertices.size(), [&](int v) { return toPlanes * other.m_vertices[v]; });
        return firstSeparating(planes, hint, [&](int f) {
            const btScalar* p = planes.m_faces[f].m_plane;
            btScalar low, high;
            mapped.extentAlong(btVector3(p[0], p[1], p[2]), low, high);
            return low + p[3] > gap;
        });
    }
    thread_local btAlignedObjectArray<btVector3> mapped; // reused: no allocation per pair
    mapped.resize(other.m_vertices.size());
    for (int v = 0; v < other.m_vertices.size(); ++v) mapped[v] = toPlanes * other.m_vertices[v];
    return firstSeparating(planes, hint, [&](int f) {
        const btScalar* p = planes.m_faces[f].m_plane;
        const btVector3 n(p[0], p[1], p[2]);
        btScalar nearest = BT_LARGE_FLOAT;
        for (int v = 0; v < mapped.size() && nearest > gap; ++v) nearest = btMin(nearest, n.dot(mapped[v]) + p[3]);
        return nearest > gap;
    });
}

// Whether the broadphase boxes of two whole bodies (not a group's leaf, which comes with its
// child shape) are apart. Each is the body's box grown by its margin and at least its contact
// breaking threshold (FragmentHull::getAabb, plus the world's growth), so boxes apart mean no
// contact point within the pair's threshold. The broadphase pairs boxes by its own fattened
// leaves (Bullet's tree grows them by 5 cm), so in a heap of 10 cm tets most pairs it gives
// are apart by these boxes: rejected here before any plane is tested.
bool bodyBoxesApart(const btCollisionObjectWrapper* a, const btCollisionObjectWrapper* b) {
    const btCollisionObject* objectA = a->getCollisionObject();
    const btCollisionObject* objectB = b->getCollisionObject();
    if (a->getCollisionShape() != objectA->getCollisionShape() || b->getCollisionShape() != objectB->getCollisionShape())
        return false;
    const btBroadphaseProxy* boxA = objectA->getBroadphaseHandle();
    const btBroadphaseProxy* boxB = objectB->getBroadphaseHandle();
    return boxA && boxB && !TestAabbAgainstAabb2(boxA->m_aabbMin, boxA->m_aabbMax, boxB->m_aabbMin, boxB->m_aabbMax);
}

} // namespace

const btConvexPolyhedron* polyhedronOf(const btCollisionObjectWrapper* w) {
    return static_cast<const btPolyhedralConvexShape*>(w->getCollisionShape())->getConvexPolyhedron();
}

namespace {

// separatingFace with b placed in a's frame by `bToA`; `aToB()` gives its inverse (made only
// when b's faces are tried).
template <typename AToB>
int separatingFaceBetween(const btConvexPolyhedron& polyA, const btConvexPolyhedron& polyB, const btTransform& bToA,
                          const AToB& aToB, btScalar gap, int hint) {
    const int facesA = polyA.m_faces.size();
    if (hint >= facesA + polyB.m_faces.size()) hint = -1; // from before a hull changed
    const auto ofA = [&](int h) { return separatingFaceOf(polyA, polyB, bToA, gap, h); };
    const auto ofB = [&](int h) {
        const int g = separatingFaceOf(polyB, polyA, aToB(), gap, h);
        return g < 0 ? -1 : facesA + g;
    };
    if (hint >= facesA) {
        const int g = ofB(hint - facesA);
        return g >= 0 ? g : ofA(-1);
    }
    const int f = ofA(hint);
    return f >= 0 ? f : ofB(-1);
}

} // namespace

int separatingFace(const btCollisionObjectWrapper* a, const btCollisionObjectWrapper* b, btScalar gap, int hint) {
    const btConvexPolyhedron* polyA = polyhedronOf(a);
    const btConvexPolyhedron* polyB = polyhedronOf(b);
    if (!polyA || !polyB) return -1;
    const btTransform bToA = a->getWorldTransform().inverseTimes(b->getWorldTransform());
    return separatingFaceBetween(*polyA, *polyB, bToA, [&bToA] { return bToA.inverse(); }, gap, hint);
}

int separatingFace(const btConvexPolyhedron& a, const btConvexPolyhedron& b, const RelativePose& pose, btScalar gap,
                   int hint) {
    return separatingFaceBetween(a, b, pose.bToA, [&pose]() -> const btTransform& { return pose.aToB; }, gap, hint);
}

bool separatedByAFacePlane(const btCollisionObjectWrapper* a, const btCollisionObjectWrapper* b, btScalar gap) {
    return separatingFace(a, b, gap) >= 0;
}

FragmentPairAlgorithm::FragmentPairAlgorithm(const btCollisionAlgorithmConstructionInfo& ci,
                                             const btCollisionObjectWrapper* body0, const btCollisionObjectWrapper* body1)
    : btActivatingCollisionAlgorithm(ci, body0, body1), givenManifold_(ci.m_manifold) {}

FragmentPairAlgorithm::~FragmentPairAlgorithm() {
    if (ownsSatManifold_) m_dispatcher->releaseManifold(satManifold_);
    if (!inner_) return;
    inner_->~btCollisionAlgorithm();
    m_dispatcher->freeCollisionAlgorithm(inner_);
}

btPersistentManifold* FragmentPairAlgorithm::manifold() {
    if (satManifold_) return satManifold_;
    return inner_ ? soleManifold(*inner_) : nullptr;
}

btScalar FragmentPairAlgorithm::threshold(const btCollisionShape* a, const btCollisionShape* b) {
    if (a != thresholdShapes_[0] || b != thresholdShapes_[1] || gContactBreakingThreshold != thresholdFactor_) {
        // Bullet keeps manifold points up to the smaller of the two shapes' thresholds; the
        // larger one here is on the safe side.
        threshold_ = btMax(a->getContactBreakingThreshold(gContactBreakingThreshold),
                           b->getContactBreakingThreshold(gContactBreakingThreshold));
        thresholdShapes_[0] = a;
        thresholdShapes_[1] = b;
        thresholdFactor_ = gContactBreakingThreshold;
    }
    return threshold_;
}

void FragmentPairAlgorithm::processCollision(const btCollisionObjectWrapper* body0, const btCollisionObjectWrapper* body1,
                                             const btDispatcherInfo& info, btManifoldResult* result) {
    auto apart = [&] {
        if (bodyBoxesApart(body0, body1)) return true;
        const auto* shape0 = static_cast<const btConvexShape*>(body0->getCollisionShape());
        const auto* shape1 = static_cast<const btConvexShape*>(body1->getCollisionShape());
        separatingFace_ =
            separatingFace(body0, body1, shape0->getMargin() + shape1->getMargin() + threshold(shape0, shape1), separatingFace_);
        return separatingFace_ >= 0;
    };
    if (apart()) {
        // No contact this step: points kept from earlier steps go too, as Bullet's own
        // refresh would drop them at this distance.
        if (btPersistentManifold* kept = manifold()) kept->clearManifold();
        return;
    }
    // Bullet's flow for this case (btConvexConvexAlgorithm with m_enableSatConvex), cheaper.
    if (const btConvexPolyhedron *polyA = polyhedronOf(body0), *polyB = polyhedronOf(body1);
        polyA && polyB && info.m_enableSatConvex && result->m_closestPointDistanceThreshold <= 0 && !inner_) {
        if (!satManifold_) {
            satManifold_ = givenManifold_;
            if (!satManifold_) {
                satManifold_ = m_dispatcher->getNewManifold(body0->getCollisionObject(), body1->getCollisionObject());
                ownsSatManifold_ = true;
            }
        }
        result->setPersistentManifold(satManifold_);
        polyhedronContacts(*polyA, body0->getWorldTransform(), *polyB, body1->getWorldTransform(),
                           satManifold_->getContactBreakingThreshold(), *result, &separatingAxis_);
        if (ownsSatManifold_) result->refreshContactPoints();
        return;
    }
    if (!inner_) {
        btCollisionAlgorithmConstructionInfo ci(m_dispatcher, 0);
        ci.m_manifold = givenManifold_;
        inner_ = configurationHullHull(m_dispatcher)->CreateCollisionAlgorithm(ci, body0, body1);
    }
    inner_->processCollision(body0, body1, info, result);
}

btScalar FragmentPairAlgorithm::calculateTimeOfImpact(btCollisionObject* body0, btCollisionObject* body1,
                                                      const btDispatcherInfo& info, btManifoldResult* result) {
    return inner_ ? inner_->calculateTimeOfImpact(body0, body1, info, result) : btScalar(1);
}

void FragmentPairAlgorithm::getAllContactManifolds(btManifoldArray& manifolds) {
    if (ownsSatManifold_) manifolds.push_back(satManifold_);
    if (inner_) inner_->getAllContactManifolds(manifolds);
}

btCollisionAlgorithm* FragmentPairCreateFunc::CreateCollisionAlgorithm(btCollisionAlgorithmConstructionInfo& ci,
                                                                       const btCollisionObjectWrapper* body0,
                                                                       const btCollisionObjectWrapper* body1) {
    if (!isFragmentHull(body0->getCollisionShape()) && !isFragmentHull(body1->getCollisionShape()))
        return configurationHullHull(ci.m_dispatcher1)->CreateCollisionAlgorithm(ci, body0, body1);
    void* memory = ci.m_dispatcher1->allocateCollisionAlgorithm(int(sizeof(FragmentPairAlgorithm)));
    return new (memory) FragmentPairAlgorithm(ci, body0, body1);
}

btCollisionAlgorithm* newFragmentPair(btDispatcher* dispatcher, const btCollisionObjectWrapper* a,
                                      const btCollisionObjectWrapper* b) {
    btCollisionAlgorithmConstructionInfo ci; // as btCollisionDispatcher::findAlgorithm makes it
    ci.m_dispatcher1 = dispatcher;
    ci.m_manifold = nullptr;
    void* memory = dispatcher->allocateCollisionAlgorithm(int(sizeof(FragmentPairAlgorithm)));
    return new (memory) FragmentPairAlgorithm(ci, a, b);
}

} // namespace shatter
