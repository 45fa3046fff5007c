// Bullet's ray and convex-sweep queries reach the group shape through processAllTriangles,
// with no help from the application: exact faces, gaps stay gaps.
#include "tests/bullet_ext/shape/group_scene.h"

#include <gtest/gtest.h>

using namespace shatter;
using namespace shatter::test;

namespace {

// table(): top 0.8 x 0.05 x 0.6 with its upper face at y = 0.55; legs 0.06 square, 0.5 high,
// centred at x = ±0.37, z = ±0.27.
constexpr double kTopY = 0.55;

// Closest hit that also records which primitive was hit.
struct ClosestHit : btCollisionWorld::ClosestRayResultCallback {
    int primitive = -2;
    ClosestHit(const btVector3& from, const btVector3& to) : ClosestRayResultCallback(from, to) {}
    btScalar addSingleResult(btCollisionWorld::LocalRayResult& r, bool normalInWorldSpace) override {
        primitive = r.m_localShapeInfo ? r.m_localShapeInfo->m_shapePart : -1;
        return ClosestRayResultCallback::addSingleResult(r, normalInWorldSpace);
    }
};

struct TableScene {
    GroupWorld w;
    btRigidBody* table;
    explicit TableScene(const btTransform& pose = btTransform::getIdentity()) {
        table = w.addStaticGroup(shatter::test::table(), pose, kGroupMargin);
        w.world().updateAabbs();
    }
};

void expectNear(const btVector3& a, const btVector3& b, double tol) {
    EXPECT_NEAR(a.x(), b.x(), tol);
    EXPECT_NEAR(a.y(), b.y(), tol);
    EXPECT_NEAR(a.z(), b.z(), tol);
}

} // namespace

TEST(GroupShapeRay, HitsTheTopFaceExactly) {
    TableScene s;
    const btVector3 from(0.1f, 2.0f, 0.05f), to(0.1f, -1.0f, 0.05f);
    ClosestHit hit(from, to);
    s.w.world().rayTest(from, to, hit);
    ASSERT_TRUE(hit.hasHit());
    EXPECT_EQ(hit.m_collisionObject, s.table);
    EXPECT_EQ(hit.primitive, 0); // the top
    EXPECT_NEAR(double(hit.m_closestHitFraction) * 3.0, 2.0 - kTopY, 1e-5); // distance along the ray
    expectNear(hit.m_hitPointWorld, btVector3(0.1f, btScalar(kTopY), 0.05f), 1e-5);
    expectNear(hit.m_hitNormalWorld, btVector3(0, 1, 0), 1e-5);
}

TEST(GroupShapeRay, HitsALegFromTheSideWithItsFaceNormal) {
    TableScene s;
    const btVector3 from(-2.0f, 0.25f, 0.27f), to(2.0f, 0.25f, 0.27f);
    ClosestHit hit(from, to);
    s.w.world().rayTest(from, to, hit);
    ASSERT_TRUE(hit.hasHit());
    EXPECT_EQ(hit.primitive, 2); // legs 1-4 are at (-x,-z), (-x,+z), (+x,-z), (+x,+z)
    EXPECT_NEAR(double(hit.m_closestHitFraction) * 4.0, 2.0 - 0.4, 1e-5);
    expectNear(hit.m_hitNormalWorld, btVector3(-1, 0, 0), 1e-5);
}

TEST(GroupShapeRay, MissesThroughTheGapBetweenTheLegs) {
    TableScene s;
    for (const auto& [from, to] : {std::pair{btVector3(-2, 0.25f, 0), btVector3(2, 0.25f, 0)},   // under the top
                                   std::pair{btVector3(0, 0.25f, -2), btVector3(0, 0.25f, 2)},
                                   std::pair{btVector3(-0.5f, 0.3f, 0), btVector3(-0.2f, 0.3f, 0)}}) { // beside a leg
        btCollisionWorld::ClosestRayResultCallback hit(from, to);
        s.w.world().rayTest(from, to, hit);
        EXPECT_FALSE(hit.hasHit()) << "hit at " << hit.m_hitPointWorld.x() << " " << hit.m_hitPointWorld.y() << " "
                                   << hit.m_hitPointWorld.z();
    }
}

TEST(GroupShapeRay, FollowsTheBodyTransform) {
    const btTransform pose(btQuaternion(btVector3(0, 1, 0), 0.5f) * btQuaternion(btVector3(1, 0, 0), 0.2f),
                           btVector3(3, 1, -2));
    TableScene s(pose);
    // A ray along the top face's normal, aimed at a point of the face.
    const btVector3 onTop = pose * btVector3(0.1f, btScalar(kTopY), 0.05f);
    const btVector3 normal = pose.getBasis() * btVector3(0, 1, 0);
    const btVector3 from = onTop + normal * 2, to = onTop - normal;
    ClosestHit hit(from, to);
    s.w.world().rayTest(from, to, hit);
    ASSERT_TRUE(hit.hasHit());
    expectNear(hit.m_hitPointWorld, onTop, 1e-5);
    expectNear(hit.m_hitNormalWorld, normal, 1e-5);
}

TEST(GroupShapeSweep, SphereSweepStopsOnTheTopWithItsNormal) {
    TableScene s;
    btSphereShape sphere(0.1f);
    const btTransform from(btQuaternion::getIdentity(), btVector3(0.1f, 2.0f, 0.05f));
    const btTransform to(btQuaternion::getIdentity(), btVector3(0.1f, 0.0f, 0.05f));
    btCollisionWorld::ClosestConvexResultCallback hit(from.getOrigin(), to.getOrigin());
    s.w.world().convexSweepTest(&sphere, from, to, hit);
    ASSERT_TRUE(hit.hasHit());
    EXPECT_EQ(hit.m_hitCollisionObject, s.table);
    // The sphere stops touching the top face grown by the group's margin (Bullet gives the
    // swept triangles the shape's margin), as it would against Bullet's own hulls.
    const double centreY = 2.0 - 2.0 * double(hit.m_closestHitFraction);
    EXPECT_NEAR(centreY, kTopY + 0.1 + kGroupMargin, 2e-3);
    expectNear(hit.m_hitNormalWorld, btVector3(0, 1, 0), 1e-3);
}

TEST(GroupShapeSweep, SmallSphereSweepsThroughTheGap) {
    TableScene s;
    btSphereShape sphere(0.05f);
    const btTransform from(btQuaternion::getIdentity(), btVector3(-2, 0.25f, 0));
    const btTransform to(btQuaternion::getIdentity(), btVector3(2, 0.25f, 0));
    btCollisionWorld::ClosestConvexResultCallback hit(from.getOrigin(), to.getOrigin());
    s.w.world().convexSweepTest(&sphere, from, to, hit);
    EXPECT_FALSE(hit.hasHit());
}
