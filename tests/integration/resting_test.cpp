// Whole pipeline on the demo meshes: OBJ -> physical mesh -> group-shape body in a Bullet
// world. Bodies must come to rest on the ground and then stay put, and runs are repeatable.
#include <shatter/bullet_ext/Plugin.h>
#include <shatter/plugin/geometry/ObjFile.h>
#include "tests/support/TestWorld.h"

#include <gtest/gtest.h>

using namespace shatter;

namespace {

std::string asset(const std::string& name) { return std::string(SHATTER_SOURCE_DIR) + "/demos/assets/" + name; }

btTransform dropPose(double height) {
    return btTransform(btQuaternion(btVector3(0, 0, 1), btScalar(0.2)), btVector3(0, btScalar(height), 0));
}

struct Case {
    const char* file;
    double rollingFriction; // m: the round bowl needs rolling resistance to stop rocking
};

class Resting : public ::testing::TestWithParam<Case> {};

BodySettings settingsFor(const Case& c) {
    BodySettings s;
    s.rigidBody.rollingFriction = c.rollingFriction;
    return s;
}

constexpr int kSettleSteps = 6 * 240;

// Settle for 6 s (the round bowl rocks for a while), then 1000 more steps (1/240 s) with the
// bodies kept awake: the resting pose must not move, so the contacts alone hold it.
// Tolerances: 0.5 mm of drift and sinking, 1e-3 rad of rotation, 5 mm/s of speed. Bullet
// solves contacts in single precision with a small penetration correction, so sub-millimetre
// motion is its noise floor; a sliding or jittering body exceeds these by orders of magnitude.
// The world uses two friction directions per contact (as the demos do): with Bullet's default
// single direction, a body kept awake creeps by about 0.2 mm/s whatever its shape (Bullet's
// own compound shape too), which the sleeping test below shows is harmless by default.
TEST_P(Resting, ComesToRestAndStaysWithoutDriftOrSinking) {
    test::TestWorld w;
    w.world.getSolverInfo().m_solverMode |= SOLVER_USE_2_FRICTION_DIRECTIONS;
    w.addGround();
    Plugin plugin(w.world);
    const auto object = geometry::buildPhysicalObject(geometry::loadObj(asset(GetParam().file)));
    auto added = plugin.addObject(object, settingsFor(GetParam()), dropPose(0.5));
    // Keep Bullet from putting the bodies to sleep: the contacts themselves must hold them still.
    for (auto* b : added.bodies) b->rigidBody().setActivationState(DISABLE_DEACTIVATION);
    w.step(kSettleSteps);
    std::vector<btTransform> settled;
    for (auto* b : added.bodies) settled.push_back(b->rigidBody().getWorldTransform());
    w.step(1000);
    for (size_t i = 0; i < added.bodies.size(); ++i) {
        const btRigidBody& rb = added.bodies[i]->rigidBody();
        const btTransform& now = rb.getWorldTransform();
        const btVector3 d = now.getOrigin() - settled[i].getOrigin();
        SCOPED_TRACE(added.bodies[i]->name());
        EXPECT_LT(std::hypot(double(d.x()), double(d.z())), 5e-4) << "horizontal drift";
        EXPECT_LT(std::abs(double(d.y())), 5e-4) << "sinking or rising";
        EXPECT_LT(double(now.getRotation().angleShortestPath(settled[i].getRotation())), 1e-3);
        EXPECT_LT(double(rb.getLinearVelocity().length()), 5e-3);
        // Above the ground: no vertex of the visual mesh is below it by more than 2 mm.
        double lowest = INFINITY;
        for (const auto& p : added.bodies[i]->visualMesh().positions) lowest = std::min(lowest, p.y());
        EXPECT_GT(lowest, -2e-3);
        EXPECT_LT(lowest, 0.05) << "it should be on the ground, not floating";
    }
}


// With Bullet's defaults untouched (single friction direction, sleeping on), every demo
// body comes to rest and falls asleep within 6 s, and then does not move at all.
TEST_P(Resting, FallsAsleepWithBulletsDefaults) {
    test::TestWorld w;
    w.addGround();
    Plugin plugin(w.world);
    const auto object = geometry::buildPhysicalObject(geometry::loadObj(asset(GetParam().file)));
    auto added = plugin.addObject(object, settingsFor(GetParam()), dropPose(0.5));
    w.step(kSettleSteps);
    std::vector<btVector3> settled;
    for (auto* b : added.bodies) settled.push_back(b->rigidBody().getCenterOfMassPosition());
    w.step(1000);
    for (size_t i = 0; i < added.bodies.size(); ++i) {
        SCOPED_TRACE(added.bodies[i]->name());
        EXPECT_FALSE(added.bodies[i]->rigidBody().isActive());
        EXPECT_EQ((added.bodies[i]->rigidBody().getCenterOfMassPosition() - settled[i]).length(), 0.0f);
    }
}

INSTANTIATE_TEST_SUITE_P(DemoMeshes, Resting,
                         ::testing::Values(Case{"chair.obj", 0.0}, Case{"torus.obj", 0.0}, Case{"bowl.obj", 0.001},
                                           Case{"hinged_planks.obj", 0.0}),
                         [](const auto& info) {
                             const std::string n = info.param.file;
                             return n.substr(0, n.find('.'));
                         });

} // namespace

TEST(Determinism, SameSceneGivesBitIdenticalTransforms) {
    auto run = [] {
        test::TestWorld w;
        w.addGround();
        Plugin plugin(w.world);
        for (const char* name : {"chair.obj", "torus.obj"}) {
            const auto object = geometry::buildPhysicalObject(geometry::loadObj(asset(name)));
            plugin.addObject(object, {}, dropPose(name[0] == 'c' ? 0.4 : 1.2));
        }
        w.step(400);
        std::vector<float> state;
        for (const auto& b : plugin.bodies()) {
            const btTransform& t = b->rigidBody().getWorldTransform();
            for (int i = 0; i < 3; ++i) {
                state.push_back(float(t.getOrigin()[i]));
                for (int j = 0; j < 3; ++j) state.push_back(float(t.getBasis()[i][j]));
            }
        }
        return state;
    };
    const auto a = run();
    const auto b = run();
    ASSERT_EQ(a.size(), b.size());
    EXPECT_EQ(0, std::memcmp(a.data(), b.data(), a.size() * sizeof(float)));
}
