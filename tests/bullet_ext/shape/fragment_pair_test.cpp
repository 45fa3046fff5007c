// Fragment hull pairs: a face-plane test proves most pairs in a heap apart before Bullet's
// convex-convex algorithm runs; pairs it cannot separate get exactly Bullet's contacts, and an
// application's own hulls are left to Bullet.
#include <shatter/bullet_ext/shape/FragmentHull.h>
#include <shatter/bullet_ext/shape/FragmentPairAlgorithm.h>
#include <shatter/bullet_ext/shape/GroupCollisionAlgorithms.h>
#include <shatter/bullet_ext/shape/GroupShape.h>
#include <shatter/bullet_ext/shape/HullLanes.h>
#include <shatter/plugin/geometry/ConvexPolyhedron.h>

#include "tests/bullet_ext/shape/same_shape.h"

#include <BulletCollision/CollisionDispatch/btConvexConvexAlgorithm.h>
#include <BulletCollision/NarrowPhaseCollision/btGjkEpaPenetrationDepthSolver.h>
#include <BulletCollision/NarrowPhaseCollision/btGjkPairDetector.h>
#include <BulletCollision/NarrowPhaseCollision/btPointCollector.h>
#include <btBulletDynamicsCommon.h>
#include <gtest/gtest.h>

#include <array>
#include <cstring>
#include <memory>

namespace shatter {
namespace {

// A tetrahedron hull (a lattice fragment of one tet) of edge about `size`, by makeFragmentHull.
std::unique_ptr<btConvexHullShape> tetFragment(double size) {
    const std::vector<Eigen::Vector3d> v = {{0, 0, 0}, {size, 0, 0}, {0, size, 0}, {0, 0, size}};
    const std::vector<std::vector<int>> f = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
    GroupShape group({geometry::ConvexPolyhedron::create(v, f, {0, 1, 2, 3}, "tet")}, 0.0005);
    return makeFragmentHull(group.primitives(), 0.0005);
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

// A lattice piece of several tets (a box of 5, off the frame's origin) collides as a hull with
// Bullet's own polyhedral features (now from convexHullOf), over all its corners: the same
// points, faces, planes, edges, centre and bounds as initializePolyhedralFeatures gives; only
// the inner box is found another way (inside the hull, about Bullet's size).
TEST(FragmentPair, APieceOfSeveralTetsHasBulletsFeatures) {
    std::vector<Eigen::Vector3d> corner; // corner i at (i & 1, i & 2, i & 4) of the box
    for (int i = 0; i < 8; ++i)
        corner.emplace_back(0.02 + (i & 1 ? 0.1 : 0.0), -0.03 + (i & 2 ? 0.07 : 0.0), 0.01 + (i & 4 ? 0.05 : 0.0));
    const std::array<std::array<int, 4>, 5> tets = {{{0, 1, 2, 4}, {3, 1, 2, 7}, {5, 1, 4, 7}, {6, 2, 4, 7}, {1, 2, 4, 7}}};
    std::vector<geometry::ConvexPolyhedron> primitives;
    for (const auto& t : tets) {
        std::vector<Eigen::Vector3d> v;
        for (int i : t) v.push_back(corner[size_t(i)]);
        std::vector<std::vector<int>> faces;
        for (int k = 0; k < 4; ++k) { // the face without vertex k, turned away from it
            std::vector<int> f = {(k + 1) % 4, (k + 2) % 4, (k + 3) % 4};
            if ((v[f[1]] - v[f[0]]).cross(v[f[2]] - v[f[0]]).dot(v[k] - v[f[0]]) > 0) std::swap(f[1], f[2]);
            faces.push_back(f);
        }
        primitives.push_back(geometry::ConvexPolyhedron::create(v, faces, {t[0], t[1], t[2], t[3]}, "tet"));
    }
    const GroupShape group(std::move(primitives), 0.0005);
    const auto hull = makeFragmentHull(group.primitives(), 0.0005);

    auto overCorners = [&](FragmentHull& h) {
        for (const Eigen::Vector3d& c : corner) h.addPoint(btVector3(btScalar(c.x()), btScalar(c.y()), btScalar(c.z())), false);
        h.setMargin(0.0005f);
        h.recalcLocalAabb();
    };
    // Bullet's features come from a scratch hull: setting features over a hull's existing ones
    // assigns a btConvexPolyhedron, which leaks its faces' index arrays (Bullet 3.24).
    FragmentHull scratch;
    overCorners(scratch);
    scratch.initializePolyhedralFeatures();
    btConvexPolyhedron features = *scratch.getConvexPolyhedron();
    ASSERT_EQ(features.m_faces.size(), 6); // the box's sides, each across two tets
    const btConvexPolyhedron& ours = *hull->getConvexPolyhedron();
    for (int k = 0; k < 3; ++k) {
        EXPECT_GT(ours.m_extents[k], 0.0f) << k;
        EXPECT_NEAR(ours.m_extents[k], features.m_extents[k], 0.01 * features.mE.length()) << k;
    }
    features.m_extents = ours.m_extents;
    FragmentHull bullets;
    overCorners(bullets);
    bullets.setPolyhedralFeatures(features);
    test::expectSameHull(*hull, bullets);
}

// A fragment's hull keeps its features in lanes (HullLanes.h), as a group's leaf hulls do, so
// the face-plane and separating-axis tests against a group's leaves read them instead of
// putting them into lanes per pair: a single tet's, a piece's of several tets and a shard's,
// each the lanes HullLanes::assign makes of the features (the same floats the tests read).
TEST(FragmentPair, AFragmentsHullKeepsItsFeaturesInLanes) {
    const auto expectKept = [](const btConvexHullShape& hull, const char* what) {
        const btConvexPolyhedron* features = hull.getConvexPolyhedron();
        ASSERT_NE(features, nullptr) << what;
        const HullLanes* kept = keptLanes(*features);
        ASSERT_NE(kept, nullptr) << what;
        HullLanes fresh;
        fresh.assign(*features);
        ASSERT_EQ(kept->vertexBlocks, fresh.vertexBlocks) << what;
        ASSERT_EQ(kept->faceBlocks, fresh.faceBlocks) << what;
        EXPECT_GT(kept->vertexBlocks + kept->faceBlocks, 0) << what;
        const auto same = [](const Float4& x, const Float4& y) {
            return std::memcmp(&x, &y, sizeof(Float4)) == 0;
        };
        for (int k = 0; k < kept->vertexBlocks; ++k)
            EXPECT_TRUE(same(kept->vertices[k].x, fresh.vertices[k].x) && same(kept->vertices[k].y, fresh.vertices[k].y) &&
                        same(kept->vertices[k].z, fresh.vertices[k].z))
                << what << " vertex block " << k;
        for (int k = 0; k < kept->faceBlocks; ++k)
            EXPECT_TRUE(same(kept->faceNormals[k].x, fresh.faceNormals[k].x) &&
                        same(kept->faceNormals[k].y, fresh.faceNormals[k].y) &&
                        same(kept->faceNormals[k].z, fresh.faceNormals[k].z) &&
                        same(kept->faceOffsets[k], fresh.faceOffsets[k]))
                << what << " face block " << k;
    };
    expectKept(*tetFragment(0.1), "tet");
    // Two tets sharing a face: a piece of several tets (convexHullOf's features), and its shard.
    const std::vector<Eigen::Vector3d> v = {{0, 0, 0}, {0.1, 0, 0}, {0, 0.1, 0}, {0, 0, 0.1}, {0.1, 0.1, 0.1}};
    const std::vector<std::vector<int>> f = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
    const std::vector<std::vector<int>> g = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
    const GroupShape group({geometry::ConvexPolyhedron::create({v[0], v[1], v[2], v[3]}, f, {0, 1, 2, 3}, "tet"),
                            geometry::ConvexPolyhedron::create({v[4], v[1], v[3], v[2]}, g, {4, 1, 3, 2}, "tet")},
                           0.0005);
    expectKept(*makeFragmentHull(group.primitives(), 0.0005), "piece");
    expectKept(*makeShardHull(group.primitives(), 0.0005, 0.01), "shard");
    // Features set over a fragment's kept ones (Bullet assigns them; over empty ones here, as
    // assigning over faces leaks their index arrays in Bullet 3.24): lanes made again.
    FragmentHull hull;
    hull.buildFeatures([](btConvexPolyhedron&) {});
    btConvexPolyhedron other = *makeFragmentHull(group.primitives(), 0.0005)->getConvexPolyhedron();
    hull.setPolyhedralFeatures(other);
    expectKept(hull, "features set");
    EXPECT_EQ(hull.getConvexPolyhedron()->m_vertices.size(), other.m_vertices.size());
}

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
