#include <shatter/bullet_ext/shape/FragmentHull.h>

#include <shatter/bullet_ext/Convert.h>
#include <shatter/bullet_ext/shape/ConvexHullOfPoints.h>
#include <shatter/bullet_ext/shape/HullLanes.h>

#include <BulletCollision/CollisionShapes/btConvexPolyhedron.h>

#include <new>
#include <typeinfo>
#include <vector>

namespace shatter {

void FragmentHull::getAabb(const btTransform& t, btVector3& aabbMin, btVector3& aabbMax) const {
    const btVector3* points = getUnscaledPoints();
    aabbMin = aabbMax = t * (points[0] * getLocalScaling());
    for (int i = 1; i < getNumPoints(); ++i) {
        const btVector3 p = t * (points[i] * getLocalScaling());
        aabbMin.setMin(p);
        aabbMax.setMax(p);
    }
    // The world grows every box by gContactBreakingThreshold; this one should be grown by the
    // margin and by the hull's own contact breaking threshold only (the distance its manifolds
    // keep points at), so the growth the world adds is taken off first.
    const btScalar grow = getMargin() + getContactBreakingThreshold(gContactBreakingThreshold) - gContactBreakingThreshold;
    const btVector3 g(grow, grow, grow);
    aabbMin -= g;
    aabbMax += g;
    // Never inside out: a box smaller than the points is no box.
    const btVector3 centre = btScalar(0.5) * (aabbMin + aabbMax);
    aabbMin.setMin(centre);
    aabbMax.setMax(centre);
}

bool isFragmentHull(const btCollisionShape* shape) { return dynamic_cast<const FragmentHull*>(shape) != nullptr; }

btScalar FragmentHull::getAngularMotionDisc() const {
    btVector3 lo, hi;
    getCachedLocalAabb(lo, hi);
    return (btScalar(0.5) * (lo + hi)).length() + btScalar(0.5) * (hi - lo).length();
}

btConvexPolyhedron& FragmentHull::emptyFeatures() {
    // As Bullet's own setPolyhedralFeatures allocates it (~btPolyhedralConvexShape frees it
    // through its virtual destructor).
    if (m_polyhedron) {
        m_polyhedron->~btConvexPolyhedron();
        btAlignedFree(m_polyhedron);
    }
    m_polyhedron = new (btAlignedAlloc(sizeof(LanedPolyhedron), 16)) LanedPolyhedron;
    return *m_polyhedron;
}

void FragmentHull::featuresSet() {
    if (m_polyhedron && typeid(*m_polyhedron) == typeid(LanedPolyhedron))
        static_cast<LanedPolyhedron*>(m_polyhedron)->refreshLanes();
}

void FragmentHull::setPolyhedralFeatures(btConvexPolyhedron& polyhedron) {
    btConvexHullShape::setPolyhedralFeatures(polyhedron);
    featuresSet();
}

namespace {

// Each corner of `primitives` once (primitives share their corners: equal global ids), in the
// order of their ids.
std::vector<Eigen::Vector3d> uniqueCorners(const std::vector<geometry::ConvexPolyhedron>& primitives) {
    std::vector<const Eigen::Vector3d*> corner;
    for (const auto& p : primitives)
        for (size_t v = 0; v < p.vertices().size(); ++v) {
            const int id = p.globalIds()[v];
            if (id >= int(corner.size())) corner.resize(size_t(id) + 1, nullptr);
            if (!corner[id]) corner[id] = &p.vertices()[v];
        }
    std::vector<Eigen::Vector3d> points;
    points.reserve(corner.size());
    for (const Eigen::Vector3d* v : corner)
        if (v) points.push_back(*v);
    return points;
}

} // namespace

std::unique_ptr<btConvexHullShape> makeFragmentHull(const std::vector<geometry::ConvexPolyhedron>& primitives,
                                                    double margin) {
    const std::vector<Eigen::Vector3d> corners = uniqueCorners(primitives);
    auto hull = std::make_unique<FragmentHull>();
    for (const Eigen::Vector3d& v : corners) hull->addPoint(toBullet(v), false);
    hull->setMargin(btScalar(margin));
    hull->recalcLocalAabb();
    // Polyhedral features make Bullet's hull-hull algorithm clip faces for a full contact
    // manifold every step (GJK finds the normal) instead of adding one GJK point per step:
    // heaps of tets rest more quietly and cost less. A single tet's features are those a
    // group shape gives its one child (exact faces, no hull to compute); a piece of several
    // tets gets Bullet's features from convexHullOf, at a fraction of
    // initializePolyhedralFeatures' cost. All corners stay the hull's points (GJK's support
    // visits them in this order), so only the features' cost changes.
    hull->buildFeatures([&](btConvexPolyhedron& features) {
        if (primitives.size() == 1) primitiveFeatures(primitives[0], features);
        else features = convexHullOf(corners);
    });
    return hull;
}

std::unique_ptr<btConvexHullShape> makeShardHull(const std::vector<geometry::ConvexPolyhedron>& primitives,
                                                 double margin, double shrink) {
    std::vector<Eigen::Vector3d> points = uniqueCorners(primitives);
    for (Eigen::Vector3d& p : points) p *= 1.0 - shrink;
    auto hull = std::make_unique<FragmentHull>();
    hull->buildFeatures([&](btConvexPolyhedron& features) { convexHullOf(points, features); });
    const btConvexPolyhedron& features = *hull->getConvexPolyhedron();
    for (int i = 0; i < features.m_vertices.size(); ++i) hull->addPoint(features.m_vertices[i], false);
    hull->setMargin(btScalar(margin));
    hull->recalcLocalAabb();
    return hull;
}

} // namespace shatter
