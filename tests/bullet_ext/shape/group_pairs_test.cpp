// The group shape against every kind of Bullet shape, in both argument orders: bodies come to
// rest at the geometric height and contacts point the right way.
//
// Heights follow Bullet's own conventions for margins (the group's child hulls have margin
// 0.04 m, Bullet's default): two hulls with polyhedral features (Bullet's clipping path) rest
// with the solids touching; a pair with a shape without polyhedral features (sphere, capsule,
// btBoxShape) or a triangle (GJK path) rests with the hull's margin between them. (A group on a
// box rests on its surface with HullPairContacts::boxLeavesClipped: GroupOnBox tests.)
#include "tests/bullet_ext/shape/group_scene.h"

#include <BulletCollision/CollisionShapes/btHeightfieldTerrainShape.h>
#include <gtest/gtest.h>

#include <functional>

using namespace shatter;
using namespace shatter::test;

namespace {


struct Scene {
    btRigidBody* body = nullptr;   // the dynamic one
    btRigidBody* ground = nullptr; // static
    double expectedHeight = 0;     // of the body's centre of mass
};

struct Case {
    const char* name;
    // Builds the scene; groundFirst decides which body the broadphase lists first.
    std::function<Scene(GroupWorld&, bool groundFirst)> build;
};


std::unique_ptr<btConvexHullShape> boxHull(const btVector3& half) {
    auto hull = std::make_unique<btConvexHullShape>();
    for (int i = 0; i < 8; ++i)
        hull->addPoint(btVector3(i & 1 ? half.x() : -half.x(), i & 2 ? half.y() : -half.y(), i & 4 ? half.z() : -half.z()),
                       false);
    hull->setMargin(btScalar(kGroupMargin));
    hull->recalcLocalAabb();
    hull->initializePolyhedralFeatures();
    return hull;
}

// Adds ground and body in the requested order.
Scene inOrder(bool groundFirst, const std::function<btRigidBody*()>& ground, const std::function<btRigidBody*()>& body,
              double expectedHeight) {
    Scene s;
    if (groundFirst) s.ground = ground();
    s.body = body();
    if (!groundFirst) s.ground = ground();
    s.expectedHeight = expectedHeight;
    return s;
}

double tableHeight(double gap) { return restHeight(toBodyFrame(table()), gap); }

const Case kCases[] = {
    {"group_on_box", [](GroupWorld& w, bool first) {
         return inOrder(first, [&] { return w.add(std::make_unique<btBoxShape>(btVector3(2, 0.1f, 2)), 0, at(0, -0.1, 0)); },
                        [&] { return w.addGroup(table(), at(0, 0.05, 0), kGroupMargin); }, tableHeight(kGroupMargin));
     }},
    {"group_on_hull", [](GroupWorld& w, bool first) {
         return inOrder(first, [&] { return w.add(boxHull(btVector3(2, 0.1f, 2)), 0, at(0, -0.1, 0)); },
                        [&] { return w.addGroup(table(), at(0, 0.05, 0), kGroupMargin); }, tableHeight(0.0));
     }},
    {"group_on_compound", [](GroupWorld& w, bool first) {
         return inOrder(first, [&] { return w.addCompound(slabFloor(3, 3, 1.0), at(0, 0, 0), kGroupMargin, 0.0); },
                        [&] { return w.addGroup(table(), at(0.05, 0.05, 0.08), kGroupMargin); }, tableHeight(0.0));
     }},
    {"group_on_triangle_mesh", [](GroupWorld& w, bool first) {
         btTriangleMesh& mesh = w.keep(std::make_unique<btTriangleMesh>());
         mesh.addTriangle(btVector3(-3, 0, -3), btVector3(-3, 0, 3), btVector3(3, 0, 3));
         mesh.addTriangle(btVector3(-3, 0, -3), btVector3(3, 0, 3), btVector3(3, 0, -3));
         return inOrder(first, [&] { return w.add(std::make_unique<btBvhTriangleMeshShape>(&mesh, true), 0, at(0, 0, 0)); },
                        [&] { return w.addGroup(table(), at(0.1, 0.05, 0.2), kGroupMargin); }, tableHeight(kGroupMargin));
     }},
    {"group_on_heightfield", [](GroupWorld& w, bool first) {
         const auto& heights = w.keep(std::make_unique<std::vector<float>>(11 * 11, 0.0f)); // flat, at y = 0
         const auto field = [&] {
             auto shape = std::make_unique<btHeightfieldTerrainShape>(11, 11, heights.data(), 1.0f, -1.0f, 1.0f, 1,
                                                                      PHY_FLOAT, false);
             shape->setLocalScaling(btVector3(0.5f, 1, 0.5f));
             return w.add(std::move(shape), 0, at(0, 0, 0));
         };
         return inOrder(first, field, [&] { return w.addGroup(table(), at(0.1, 0.05, 0.2), kGroupMargin); },
                        tableHeight(kGroupMargin));
     }},
    {"group_on_group", [](GroupWorld& w, bool first) {
         return inOrder(first, [&] { return w.addStaticGroup(slabFloor(4, 4, 0.5), at(0, 0, 0), kGroupMargin); },
                        [&] { return w.addGroup(table(), at(0.05, 0.05, 0.08), kGroupMargin); }, tableHeight(0.0));
     }},
    {"sphere_on_group", [](GroupWorld& w, bool first) {
         return inOrder(first, [&] { return w.addStaticGroup(slabFloor(4, 4, 0.5), at(0, 0, 0), kGroupMargin); },
                        [&] { return w.add(std::make_unique<btSphereShape>(0.2f), 1.0, at(0.1, 0.3, 0.1)); },
                        0.2 + kGroupMargin);
     }},
    {"capsule_on_group", [](GroupWorld& w, bool first) {
         const btTransform lying(btQuaternion(btVector3(0, 0, 1), SIMD_HALF_PI), btVector3(0.1f, 0.2f, 0.1f));
         return inOrder(first, [&] { return w.addStaticGroup(slabFloor(4, 4, 0.5), at(0, 0, 0), kGroupMargin); },
                        [&] { return w.add(std::make_unique<btCapsuleShape>(0.1f, 0.4f), 1.0, lying); },
                        0.1 + kGroupMargin);
     }},
    {"hull_on_group", [](GroupWorld& w, bool first) {
         return inOrder(first, [&] { return w.addStaticGroup(slabFloor(4, 4, 0.5), at(0, 0, 0), kGroupMargin); },
                        [&] { return w.add(boxHull(btVector3(0.2f, 0.1f, 0.3f)), 1.0, at(0.1, 0.15, 0.1)); }, 0.1);
     }},
    {"box_on_group", [](GroupWorld& w, bool first) {
         return inOrder(first, [&] { return w.addStaticGroup(slabFloor(4, 4, 0.5), at(0, 0, 0), kGroupMargin); },
                        [&] { return w.add(std::make_unique<btBoxShape>(btVector3(0.2f, 0.1f, 0.3f)), 1.0, at(0.1, 0.15, 0.1)); },
                        0.1 + kGroupMargin);
     }},
    {"compound_on_group", [](GroupWorld& w, bool first) {
         return inOrder(first, [&] { return w.addStaticGroup(slabFloor(4, 4, 0.5), at(0, 0, 0), kGroupMargin); },
                        [&] { return w.addCompound(table(), at(0.05, 0.05, 0.08), kGroupMargin); }, tableHeight(0.0));
     }},
};

struct Param {
    Case c;
    bool groundFirst;
};

void PrintTo(const Param& p, std::ostream* os) { *os << p.c.name << (p.groundFirst ? ", ground first" : ", body first"); }

class GroupAgainst : public testing::TestWithParam<Param> {};

// Normal on `body` from a closest-points query (btCollisionWorld::contactPairTest) with the
// two objects given in the order (a, b).
struct NormalOn : btCollisionWorld::ContactResultCallback {
    const btCollisionObject* body;
    btVector3 sum{0, 0, 0};
    int count = 0;
    explicit NormalOn(const btCollisionObject* b) : body(b) {}
    btScalar addSingleResult(btManifoldPoint& cp, const btCollisionObjectWrapper* w0, int, int,
                             const btCollisionObjectWrapper* w1, int, int) override {
        if (cp.getDistance() > btScalar(1e-3)) return 0;
        // m_normalWorldOnB points from object 1 towards object 0.
        if (w0->getCollisionObject() == body) sum += cp.m_normalWorldOnB;
        else if (w1->getCollisionObject() == body) sum -= cp.m_normalWorldOnB;
        ++count;
        return 0;
    }
};

TEST_P(GroupAgainst, RestsAtTheGeometricHeightWithTheGroundNormal) {
    GroupWorld w;
    const Scene s = GetParam().c.build(w, GetParam().groundFirst);
    s.body->setActivationState(DISABLE_DEACTIVATION);
    w.step(960);
    const double height = double(s.body->getCenterOfMassPosition().y());
    EXPECT_NEAR(height, s.expectedHeight, 2e-3);
    EXPECT_LT(std::abs(s.body->getLinearVelocity().y()), 1e-3); // a capsule may keep rolling: only vertical
    const btVector3 up = w.contactNormalOn(s.body, s.ground);
    EXPECT_GT(up.y(), 0.999) << up.x() << " " << up.y() << " " << up.z();

    // The same contact through contactPairTest, in both argument orders.
    for (int order = 0; order < 2; ++order) {
        NormalOn normal(s.body);
        if (order == 0)
            w.world().contactPairTest(s.body, s.ground, normal);
        else
            w.world().contactPairTest(s.ground, s.body, normal);
        ASSERT_GT(normal.count, 0) << "order " << order;
        EXPECT_GT(normal.sum.normalized().y(), 0.999) << "order " << order;
    }
}

INSTANTIATE_TEST_SUITE_P(GroupShape, GroupAgainst,
                         testing::ValuesIn([] {
                             std::vector<Param> p;
                             for (const Case& c : kCases)
                                 for (bool first : {true, false}) p.push_back({c, first});
                             return p;
                         }()),
                         [](const auto& info) {
                             return std::string(info.param.c.name) + (info.param.groundFirst ? "_ground_first" : "_body_first");
                         });

} // namespace

// Contact points name the primitives that touch (partId -1, index = primitive), on both
// sides of a group-group pair and against the plane, as Bullet does for compound children.
TEST(GroupContacts, PointsNameThePrimitivesThatTouch) {
    GroupWorld w;
    btRigidBody* plane = w.addStaticPlane(btVector3(0, 1, 0), -1.0); // out of the way, under the floor
    btRigidBody* floor = w.addStaticGroup(slabFloor(4, 4, 0.5), at(0, 0, 0), kGroupMargin);
    btRigidBody* tableBody = w.addGroup(table(), at(0.05, 0.05, 0.08), kGroupMargin);
    btRigidBody* ell = w.addGroup(lShape(), at(1.5, -0.8, 1.5), kGroupMargin); // beside the floor, on the plane
    w.step(480);
    int tableFloor = 0, ellPlane = 0;
    for (int m = 0; m < w.dispatcher().getNumManifolds(); ++m) {
        const btPersistentManifold* mf = w.dispatcher().getManifoldByIndexInternal(m);
        for (int i = 0; i < mf->getNumContacts(); ++i) {
            const btManifoldPoint& p = mf->getContactPoint(i);
            const bool tableFirst = mf->getBody0() == tableBody;
            if ((tableFirst && mf->getBody1() == floor) || (mf->getBody0() == floor && mf->getBody1() == tableBody)) {
                const int legIndex = tableFirst ? p.m_index0 : p.m_index1;
                const int slabIndex = tableFirst ? p.m_index1 : p.m_index0;
                EXPECT_GE(legIndex, 1); // legs are primitives 1-4; the top never touches the floor
                EXPECT_LE(legIndex, 4);
                EXPECT_GE(slabIndex, 0);
                EXPECT_LT(slabIndex, 16);
                EXPECT_EQ(p.m_partId0, -1);
                EXPECT_EQ(p.m_partId1, -1);
                ++tableFloor;
            }
            if ((mf->getBody0() == ell && mf->getBody1() == plane) || (mf->getBody0() == plane && mf->getBody1() == ell)) {
                const bool ellFirst = mf->getBody0() == ell;
                EXPECT_EQ(ellFirst ? p.m_partId0 : p.m_partId1, -1);
                const int index = ellFirst ? p.m_index0 : p.m_index1;
                EXPECT_TRUE(index == 0 || index == 1) << index;
                ++ellPlane;
            }
        }
    }
    EXPECT_GE(tableFloor, 4);
    EXPECT_GE(ellPlane, 3);
}

// On a floor of 10 000 slabs, a body meets only the slabs under it: one leaf manifold per
// touching primitive pair, not per primitive, and it rests like on a small floor.
TEST(GroupContacts, ALargeFloorOnlyWorksWhereTheBodyIs) {
    GroupWorld w;
    btRigidBody* floor = w.addStaticGroup(slabFloor(100, 100, 0.1), at(0, 0, 0), kGroupMargin);
    btRigidBody* body = w.addGroup(lShape(), at(0.013, 0.02, 0.027), kGroupMargin);
    w.step(480);
    EXPECT_NEAR(double(body->getCenterOfMassPosition().y()), restHeight(toBodyFrame(lShape()), 0.0), 1e-3);
    int manifolds = 0;
    for (int m = 0; m < w.dispatcher().getNumManifolds(); ++m) {
        const btPersistentManifold* mf = w.dispatcher().getManifoldByIndexInternal(m);
        if ((mf->getBody0() == floor && mf->getBody1() == body) || (mf->getBody0() == body && mf->getBody1() == floor))
            ++manifolds;
    }
    // The L's two bars cover some 30 slabs of 0.1 m; with the slabs within the contact
    // threshold around them, a few dozen pairs (52 measured) out of 2 x 10 000.
    EXPECT_GT(manifolds, 8);
    EXPECT_LT(manifolds, 80);
}
