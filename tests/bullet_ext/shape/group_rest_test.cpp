// Group bodies resting on a static plane: still, at the right height, like Bullet's compound.
#include "tests/bullet_ext/shape/group_scene.h"

#include <gtest/gtest.h>

#include <algorithm>

using namespace shatter;
using namespace shatter::test;

namespace {


struct Shape {
    const char* name;
    Primitives (*make)();
};
const Shape kShapes[] = {{"table", [] { return table(); }}, {"l_shape", lShape}};

btTransform lifted(double y, double yaw = 0.0, double tilt = 0.0) {
    return btTransform(btQuaternion(btVector3(0, 1, 0), btScalar(yaw)) * btQuaternion(btVector3(1, 0, 0), btScalar(tilt)),
                       btVector3(0, btScalar(y), 0));
}

// The design's up axis (y) in world coordinates for a body made by GroupWorld::addGroup.
btVector3 designUp(const btRigidBody* body, const BodyFrame& frame) {
    return (body->getWorldTransform() * frame.bodyToDesign.inverse()).getBasis() * btVector3(0, 1, 0);
}

// Steps until settled, then measures what the body does over `steps` more steps.
struct Stillness {
    double horizontalDrift = 0, verticalDrift = 0, maxSpeed = 0, height = 0;
};
Stillness measureRest(GroupWorld& w, btRigidBody* body, int settle, int steps) {
    body->setActivationState(DISABLE_DEACTIVATION); // a sleeping body would hide jitter
    w.step(settle);
    const btVector3 start = body->getCenterOfMassPosition();
    Stillness s;
    for (int i = 0; i < steps; ++i) {
        w.step(1);
        const btVector3 v = body->getLinearVelocity();
        const btVector3 corner = body->getVelocityInLocalPoint(btVector3(0.3f, 0.3f, 0.3f)); // includes spin
        s.maxSpeed = std::max({s.maxSpeed, double(v.length()), double(corner.length())});
    }
    const btVector3 d = body->getCenterOfMassPosition() - start;
    s.horizontalDrift = std::hypot(double(d.x()), double(d.z()));
    s.verticalDrift = std::abs(double(d.y()));
    s.height = double(body->getCenterOfMassPosition().y());
    return s;
}

void PrintTo(const Shape& s, std::ostream* os) { *os << s.name; }

class RestOnPlane : public testing::TestWithParam<Shape> {};

// A table (top + 4 legs) and an L dropped on a plane come to rest at the geometric height
// (lowest vertex one margin above the plane, as Bullet's convex-plane contact has it) and
// then stay put: no drift, no sinking, no jitter.
TEST_P(RestOnPlane, StaysStillAtTheGeometricHeight) {
    GroupWorld w;
    btRigidBody* ground = w.addStaticPlane();
    const Primitives design = GetParam().make();
    const BodyFrame frame = toBodyFrame(design);
    btRigidBody* body = w.addGroup(design, lifted(0.3, 0.3), kGroupMargin);
    const Stillness s = measureRest(w, body, 720, 1000);
    EXPECT_LT(s.horizontalDrift, 1e-4);
    EXPECT_LT(s.verticalDrift, 1e-4);
    EXPECT_LT(s.maxSpeed, 1e-3);
    EXPECT_NEAR(s.height, restHeight(frame, kGroupMargin), 1e-3);
    EXPECT_NEAR(w.contactNormalOn(body, ground).y(), 1.0, 1e-6);
    EXPECT_GE(w.contactCount(body, ground), 3);
}

// Dropped tilted, so that they land on an edge and tip over, they settle at the same height.
// Afterwards Bullet's solver leaves a steady slide of about 0.1 mm/s: with its default single
// friction direction (along the sliding velocity) and 10 iterations, the friction of four
// contacts does not converge to zero velocity. Bullet's compound of hulls does the same (0.04
// mm/s measured for the table); SOLVER_USE_2_FRICTION_DIRECTIONS cuts it 18-fold.
TEST_P(RestOnPlane, TiltedLandingSettlesAtTheSameHeight) {
    GroupWorld w;
    w.addStaticPlane();
    const Primitives design = GetParam().make();
    btRigidBody* body = w.addGroup(design, lifted(0.3, 0.3, 0.15), kGroupMargin);
    const Stillness s = measureRest(w, body, 720, 1000);
    EXPECT_NEAR(s.height, restHeight(toBodyFrame(design), kGroupMargin), 1e-3);
    EXPECT_LT(s.verticalDrift, 1e-4);
    EXPECT_LT(s.horizontalDrift, 1e-3);
    EXPECT_LT(s.maxSpeed, 1e-3);
}

// The same geometry as Bullet's compound of hulls with the same margin rests at the same
// height with the same ground normal.
TEST_P(RestOnPlane, MatchesBulletsCompoundOfHulls) {
    const Primitives design = GetParam().make();
    double heights[2];
    btVector3 normals[2];
    for (int useCompound = 0; useCompound < 2; ++useCompound) {
        GroupWorld w;
        btRigidBody* ground = w.addStaticPlane();
        btRigidBody* body = useCompound ? w.addCompound(design, lifted(0.1, 0.3), kGroupMargin)
                                        : w.addGroup(design, lifted(0.1, 0.3), kGroupMargin);
        heights[useCompound] = measureRest(w, body, 720, 10).height;
        normals[useCompound] = w.contactNormalOn(body, ground);
    }
    EXPECT_NEAR(heights[0], heights[1], 1e-3);
    EXPECT_GT(normals[0].dot(normals[1]), 1.0 - 1e-6) << normals[0].y() << " vs " << normals[1].y();
    EXPECT_NEAR(normals[0].y(), 1.0, 1e-6);
}

INSTANTIATE_TEST_SUITE_P(GroupShape, RestOnPlane, testing::ValuesIn(kShapes),
                         [](const auto& info) { return std::string(info.param.name); });

// A pallet: two runners along z and three boards across them, 0.15 m high, lowest point y = 0.
Primitives pallet() {
    Primitives p;
    for (double x : {-0.3, 0.3}) p.push_back(boxPrimitive({x, 0.05, 0}, {0.05, 0.05, 0.4}));
    for (double z : {-0.28, 0.0, 0.28}) p.push_back(boxPrimitive({0, 0.125, z}, {0.4, 0.025, 0.1}));
    return p;
}

} // namespace

// Three pallets stacked on a plane (group on plane, then group on group twice) stay standing.
TEST(GroupShapeStack, ThreePalletsStayStacked) {
    GroupWorld w;
    w.addStaticPlane();
    const BodyFrame frame = toBodyFrame(pallet());
    std::vector<btRigidBody*> bodies;
    for (int k = 0; k < 3; ++k) // small offsets and gaps so the stack has to settle
        bodies.push_back(w.addGroup(pallet(), lifted(kGroupMargin + 0.155 * k + 0.005, 0.02 * k), kGroupMargin));
    for (auto* b : bodies) b->setActivationState(DISABLE_DEACTIVATION);
    w.step(240);
    const btVector3 start = bodies[2]->getCenterOfMassPosition();
    w.step(2000);
    const btVector3 d = bodies[2]->getCenterOfMassPosition() - start;
    EXPECT_LT(std::hypot(double(d.x()), double(d.z())), 5e-3);
    for (int k = 0; k < 3; ++k) {
        const btRigidBody* b = bodies[k];
        // Pallets touch solid to solid (polyhedral pairs); the bottom one sits a margin above the plane.
        EXPECT_NEAR(double(b->getCenterOfMassPosition().y()), restHeight(frame, kGroupMargin) + 0.15 * k, 2e-3) << k;
        EXPECT_GT(double(designUp(b, frame).y()), 0.9999) << k;
    }
}

// A table whose legs stand exactly on the seams between the slabs of a group floor (one leg
// on a corner where four slabs meet) rests level with upward contact normals: the hull pairs
// take Bullet's separating-axis path, not GJK/EPA normals tilted by the neighbouring slab.
TEST(GroupShapeStack, TableOnSlabSeamsRestsLevel) {
    GroupWorld w;
    btRigidBody* floor = w.addStaticGroup(slabFloor(4, 4, 0.5), btTransform::getIdentity(), kGroupMargin);
    btRigidBody* body = w.addGroup(table(), btTransform(btQuaternion::getIdentity(), btVector3(0.13f, 0.02f, 0.23f)), kGroupMargin);
    const Stillness s = measureRest(w, body, 720, 1000);
    EXPECT_NEAR(s.height, restHeight(toBodyFrame(table()), 0.0), 1e-3);
    EXPECT_LT(s.verticalDrift, 1e-4);
    EXPECT_LT(s.horizontalDrift, 3e-3); // a slow creep: 16 contacts, 10 solver iterations (measured 1.3 mm)
    EXPECT_GT(w.contactNormalOn(body, floor).y(), 0.9999);
    EXPECT_GT(double(designUp(body, toBodyFrame(table())).y()), 0.99999);
}

// Same scene, same build: bit-identical results.
TEST(GroupShapeStack, RunsAreDeterministic) {
    const auto run = [] {
        GroupWorld w;
        w.addStaticGroup(slabFloor(4, 4, 0.5), btTransform::getIdentity(), kGroupMargin);
        std::vector<btRigidBody*> bodies;
        for (int k = 0; k < 4; ++k) {
            const btTransform pose(btQuaternion(btVector3(0.3f, 1, 0.1f).normalized(), 0.4f * k),
                                   btVector3(0.2f * k - 0.3f, 0.3f + 0.35f * k, 0.1f * k));
            bodies.push_back(k % 2 ? w.addGroup(lShape(), pose, kGroupMargin) : w.addCompound(pallet(), pose, kGroupMargin));
        }
        w.step(600);
        std::vector<float> state;
        for (auto* b : bodies) {
            const btTransform& t = b->getWorldTransform();
            for (int i = 0; i < 3; ++i) {
                state.push_back(t.getOrigin()[i]);
                for (int j = 0; j < 3; ++j) state.push_back(t.getBasis()[i][j]);
            }
        }
        return state;
    };
    const auto a = run();
    const auto b = run();
    ASSERT_EQ(a.size(), b.size());
    for (size_t i = 0; i < a.size(); ++i) EXPECT_EQ(a[i], b[i]) << i;
}
