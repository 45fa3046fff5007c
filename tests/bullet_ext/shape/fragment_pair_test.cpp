// Fragment hull pairs: a face-plane test proves most pairs in a heap apart before Bullet's
// convex-convex algorithm runs; pairs it cannot separate get exactly Bullet's contacts, and an
// application's own hulls are left to Bullet.
#include <shatter/bullet_ext/shape/FragmentHull.h>
#include <shatter/bullet_ext/shape/FragmentPairAlgorithm.h>
#include <shatter/bullet_ext/shape/GroupCollisionAlgorithms.h>
#include <shatter/bullet_ext/shape/GroupShape.h>
#include <shatter/plugin/geometry/ConvexPolyhedron.h>

#include <BulletCollision/CollisionDispatch/btConvexConvexAlgorithm.h>
#include <BulletCollision/NarrowPhaseCollision/btGjkEpaPenetrationDepthSolver.h>
#include <BulletCollision/NarrowPhaseCollision/btGjkPairDetector.h>
#include <BulletCollision/NarrowPhaseCollision/btPointCollector.h>
#include <btBulletDynamicsCommon.h>
#include <gtest/gtest.h>

#include <memory>

namespace shatter {
namespace {

// A tetrahedron hull (a lattice fragment of one tet) of edge about `size`, by makeFragmentHull.
std::unique_ptr<btConvexHullShape> tetFragment(double size) {
    const std::vector<Eigen::Vector3d> v = {{0, 0, 0}, {size, 0, 0}, {0, size, 0}, {0, 0, size}};
    const std::vector<std::vector<int>> f = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
    GroupShape group({geometry::ConvexPolyhedron::create(v, f, {0, 1, 2, 3}, "tet")}, 0.0005);
    return makeFragmentHull(group, 0.0005);
}

struct Pair {
    btDefaultCollisionConfiguration config;
    btCollisionDispatcher dispatcher{&config};
    btCollisionObject a, b;
    Pair(btCollisionShape& shapeA, btCollisionShape& shapeB, const btVector3& offset) {
        registerGroupShapeAlgorithms(dispatcher);
        a.setCollisionShape(&shapeA);
        b.setCollisionShape(&shapeB);
        b.setWorldTransform(btTransform(btQuaternion(btVector3(1, 1, 0).normalized(), 0.3f), offset));
    }
    // Contact points of one narrowphase query.
    int contacts() {
        const btCollisionObjectWrapper wa(nullptr, a.getCollisionShape(), &a, a.getWorldTransform(), -1, -1);
        const btCollisionObjectWrapper wb(nullptr, b.getCollisionShape(), &b, b.getWorldTransform(), -1, -1);
        btCollisionAlgorithm* algorithm = dispatcher.findAlgorithm(&wa, &wb, nullptr, BT_CONTACT_POINT_ALGORITHMS);
        btManifoldResult result(&wa, &wb);
        algorithm->processCollision(&wa, &wb, btDispatcherInfo(), &result);
        btManifoldArray manifolds;
        algorithm->getAllContactManifolds(manifolds);
        int points = 0;
        for (int i = 0; i < manifolds.size(); ++i) points += manifolds[i]->getNumContacts();
        algorithm->~btCollisionAlgorithm();
        dispatcher.freeCollisionAlgorithm(algorithm);
        return points;
    }
    btCollisionAlgorithm* algorithmFor() {
        const btCollisionObjectWrapper wa(nullptr, a.getCollisionShape(), &a, a.getWorldTransform(), -1, -1);
        const btCollisionObjectWrapper wb(nullptr, b.getCollisionShape(), &b, b.getWorldTransform(), -1, -1);
        return dispatcher.findAlgorithm(&wa, &wb, nullptr, BT_CONTACT_POINT_ALGORITHMS);
    }
};

TEST(FragmentPair, AnApplicationsHullsKeepBulletsAlgorithm) {
    btConvexHullShape hullA, hullB;
    for (const auto& p : {btVector3(0, 0, 0), btVector3(1, 0, 0), btVector3(0, 1, 0), btVector3(0, 0, 1)}) {
        hullA.addPoint(p);
        hullB.addPoint(p);
    }
    Pair pair(hullA, hullB, btVector3(0.2f, 0.2f, 0.2f));
    btCollisionAlgorithm* algorithm = pair.algorithmFor();
    EXPECT_NE(dynamic_cast<btConvexConvexAlgorithm*>(algorithm), nullptr);
    algorithm->~btCollisionAlgorithm();
    pair.dispatcher.freeCollisionAlgorithm(algorithm);
}

TEST(FragmentPair, TetsApartBeyondTheirThresholdMakeNoContactAndTouchingOnesDo) {
    const auto a = tetFragment(0.1), b = tetFragment(0.1);
    // b turned slightly, 5 cm beyond a's slanted face: a face plane separates them.
    Pair apart(*a, *b, btVector3(0.1f, 0.1f, 0.1f));
    const btCollisionObjectWrapper wa(nullptr, a.get(), &apart.a, apart.a.getWorldTransform(), -1, -1);
    const btCollisionObjectWrapper wb(nullptr, b.get(), &apart.b, apart.b.getWorldTransform(), -1, -1);
    EXPECT_TRUE(separatedByAFacePlane(&wa, &wb, btScalar(0.002)));
    EXPECT_EQ(apart.contacts(), 0);
    // Overlapping by a few millimetres: the same contacts as Bullet's own algorithm makes.
    Pair touching(*a, *b, btVector3(0.03f, 0.03f, 0.03f));
    const int points = touching.contacts();
    EXPECT_GT(points, 0);
    btCollisionAlgorithmConstructionInfo ci(&touching.dispatcher, 0);
    ci.m_manifold = nullptr; // this constructor leaves it unset
    const btCollisionObjectWrapper ta(nullptr, a.get(), &touching.a, touching.a.getWorldTransform(), -1, -1);
    const btCollisionObjectWrapper tb(nullptr, b.get(), &touching.b, touching.b.getWorldTransform(), -1, -1);
    btCollisionAlgorithm* bullets =
        touching.config.getCollisionAlgorithmCreateFunc(CONVEX_HULL_SHAPE_PROXYTYPE, CONVEX_HULL_SHAPE_PROXYTYPE)
            ->CreateCollisionAlgorithm(ci, &ta, &tb);
    btManifoldResult result(&ta, &tb);
    bullets->processCollision(&ta, &tb, btDispatcherInfo(), &result);
    btManifoldArray manifolds;
    bullets->getAllContactManifolds(manifolds);
    ASSERT_EQ(manifolds.size(), 1);
    EXPECT_EQ(manifolds[0]->getNumContacts(), points);
    bullets->~btCollisionAlgorithm();
    touching.dispatcher.freeCollisionAlgorithm(bullets);
}

TEST(FragmentPair, ThePlaneTestNeverSeparatesOverlappingHulls) {
    // Random poses of two tets: whenever GJK finds them within the gap, no face plane may
    // claim they are apart (the test is only ever a proof of separation).
    const auto a = tetFragment(0.1), b = tetFragment(0.07);
    btDefaultCollisionConfiguration config;
    btCollisionDispatcher dispatcher(&config);
    btCollisionObject oa, ob;
    oa.setCollisionShape(a.get());
    ob.setCollisionShape(b.get());
    std::srand(3);
    auto unit = [] { return btScalar(std::rand()) / btScalar(RAND_MAX); };
    int near = 0;
    for (int trial = 0; trial < 2000; ++trial) {
        ob.setWorldTransform(btTransform(btQuaternion(btVector3(unit() - 0.5f, unit() - 0.5f, unit() - 0.5f).normalized(),
                                                      6.0f * unit()),
                                         btVector3(0.2f * unit() - 0.05f, 0.2f * unit() - 0.05f, 0.2f * unit() - 0.05f)));
        const btCollisionObjectWrapper wa(nullptr, a.get(), &oa, oa.getWorldTransform(), -1, -1);
        const btCollisionObjectWrapper wb(nullptr, b.get(), &ob, ob.getWorldTransform(), -1, -1);
        btGjkPairDetector::ClosestPointInput input;
        input.m_transformA = oa.getWorldTransform();
        input.m_transformB = ob.getWorldTransform();
        btVoronoiSimplexSolver simplex;
        btGjkEpaPenetrationDepthSolver epa;
        btGjkPairDetector gjk(a.get(), b.get(), &simplex, &epa);
        btPointCollector closest;
        gjk.getClosestPoints(input, closest, nullptr);
        // GJK's distance is between the hulls grown by their margins; the plane test's gap is
        // between the hulls themselves.
        const btScalar gap = 0.002f, raw = closest.m_distance + a->getMargin() + b->getMargin();
        if (closest.m_hasResult && raw <= gap) {
            ++near;
            EXPECT_FALSE(separatedByAFacePlane(&wa, &wb, gap)) << "trial " << trial << " distance " << raw;
        }
    }
    EXPECT_GT(near, 100);
}

TEST(FragmentPair, WithTheSeparatingAxisTestOnAPairKeepsBulletsPointsBitForBitAlongAPath) {
    // A group's leaf against a fragment runs Bullet's separating-axis test and clip
    // (m_enableSatConvex) in its own form (polyhedronContacts), after the face-plane test: the
    // manifold must hold exactly what Bullet's own algorithm leaves in its own, step after
    // step, as a tet slides from contact out through the margins and threshold and beyond.
    const auto a = tetFragment(0.1), b = tetFragment(0.07);
    btDefaultCollisionConfiguration config;
    btCollisionDispatcher dispatcher(&config);
    registerGroupShapeAlgorithms(dispatcher);
    btDispatcherInfo info;
    info.m_enableSatConvex = true;
    btCollisionObject oa, ob;
    oa.setCollisionShape(a.get());
    ob.setCollisionShape(b.get());
    std::srand(5);
    auto unit = [] { return btScalar(std::rand()) / btScalar(RAND_MAX); };
    const btScalar planeOnly = a->getMargin() + b->getMargin() + gContactBreakingThreshold;
    int touching = 0, withinTheMargins = 0;
    for (int path = 0; path < 100; ++path) {
        const btQuaternion turn(btVector3(unit() - 0.5f, unit() - 0.5f, unit() - 0.5f).normalized(), 6.0f * unit());
        const btVector3 start(0.02f + 0.02f * unit(), 0.02f + 0.02f * unit(), 0.02f + 0.02f * unit());
        const btVector3 away = btVector3(unit(), unit(), unit()).normalized() * 0.002f; // per step
        ob.setWorldTransform(btTransform(turn, start));
        const btCollisionObjectWrapper wa(nullptr, a.get(), &oa, oa.getWorldTransform(), -1, -1);
        const btCollisionObjectWrapper wb0(nullptr, b.get(), &ob, ob.getWorldTransform(), -1, -1);
        btCollisionAlgorithm* ours = dispatcher.findAlgorithm(&wa, &wb0, nullptr, BT_CONTACT_POINT_ALGORITHMS);
        ASSERT_NE(dynamic_cast<FragmentPairAlgorithm*>(ours), nullptr);
        btCollisionAlgorithmConstructionInfo ci(&dispatcher, 0);
        ci.m_manifold = nullptr; // this constructor leaves it unset: Bullet's algorithm makes its own
        btCollisionAlgorithm* bullets =
            config.getCollisionAlgorithmCreateFunc(CONVEX_HULL_SHAPE_PROXYTYPE, CONVEX_HULL_SHAPE_PROXYTYPE)
                ->CreateCollisionAlgorithm(ci, &wa, &wb0);
        for (int step = 0; step < 30; ++step) {
            ob.setWorldTransform(btTransform(turn, start + away * btScalar(step)));
            const btCollisionObjectWrapper wb(nullptr, b.get(), &ob, ob.getWorldTransform(), -1, -1);
            if (separatedByAFacePlane(&wa, &wb, btScalar(1e-3)) && !separatedByAFacePlane(&wa, &wb, planeOnly))
                ++withinTheMargins;
            btManifoldResult r1(&wa, &wb), r2(&wa, &wb);
            ours->processCollision(&wa, &wb, info, &r1);
            bullets->processCollision(&wa, &wb, info, &r2);
            btManifoldArray m1, m2;
            ours->getAllContactManifolds(m1);
            bullets->getAllContactManifolds(m2);
            const int n1 = m1.size() ? m1[0]->getNumContacts() : 0, n2 = m2.size() ? m2[0]->getNumContacts() : 0;
            ASSERT_EQ(n1, n2) << "path " << path << " step " << step;
            touching += n1 > 0;
            for (int k = 0; k < n1; ++k) {
                const btManifoldPoint &p1 = m1[0]->getContactPoint(k), &p2 = m2[0]->getContactPoint(k);
                EXPECT_EQ(p1.m_positionWorldOnB, p2.m_positionWorldOnB);
                EXPECT_EQ(p1.m_normalWorldOnB, p2.m_normalWorldOnB);
                EXPECT_EQ(p1.getDistance(), p2.getDistance());
            }
        }
        for (btCollisionAlgorithm* algorithm : {ours, bullets}) {
            algorithm->~btCollisionAlgorithm();
            dispatcher.freeCollisionAlgorithm(algorithm);
        }
    }
    EXPECT_GT(touching, 300);
    EXPECT_GT(withinTheMargins, 100); // steps apart, but not by the face-plane test's gap
}

} // namespace
} // namespace shatter
