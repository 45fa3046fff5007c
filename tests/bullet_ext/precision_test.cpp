// What float Bullet can simulate (PrecisionLimits.h) and the warnings for bodies beyond it.
#include <shatter/bullet_ext/Plugin.h>
#include <shatter/bullet_ext/PrecisionLimits.h>
#include "tests/support/TestWorld.h"

#include <gtest/gtest.h>

#include <algorithm>

using namespace shatter;

namespace {

geometry::PhysicalMesh boxMesh(const std::string& name, double h, double density = 1000.0) {
    std::vector<Eigen::Vector3d> v;
    for (int i = 0; i < 8; ++i) v.emplace_back(i & 1 ? h : -h, i & 2 ? h : -h, i & 4 ? h : -h);
    const std::vector<std::vector<int>> f = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    geometry::PhysicalMeshSettings settings;
    settings.density = density;
    return geometry::buildPhysicalMesh(name, v, f, settings);
}

btTransform at(double y) { return btTransform(btQuaternion::getIdentity(), btVector3(0, btScalar(y), 0)); }

// Height of a plain Bullet box of `mass` kg dropped on a static ground after one second.
double boxHeightAfterFall(double mass) {
    test::TestWorld w;
    w.addGround();
    btBoxShape shape(btVector3(0.5f, 0.5f, 0.5f));
    btVector3 inertia;
    shape.calculateLocalInertia(btScalar(mass), inertia);
    btRigidBody box(btScalar(mass), nullptr, &shape, inertia);
    box.setWorldTransform(at(0.6));
    w.world.addRigidBody(&box);
    w.step(240);
    w.world.removeRigidBody(&box);
    return box.getWorldTransform().getOrigin().y();
}

bool mentions(const std::vector<std::string>& warnings, const std::string& what) {
    return std::any_of(warnings.begin(), warnings.end(), [&](const auto& w) { return w.find(what) != std::string::npos; });
}

} // namespace

// The documented bound is Bullet's own: 0.1% below it a box rests on the ground, 0.1% above
// it the solver skips its contacts and it falls through (independent of size and gravity,
// since the test is on the inverse mass alone).
TEST(PrecisionLimits, HeaviestMovableMassIsWhereBulletStopsHoldingABoxUp) {
    const double bound = heaviestMovableMass();
    EXPECT_NEAR(bound, 1.453e7, 0.001e7); // single precision, as bullet.pc builds
    EXPECT_NEAR(boxHeightAfterFall(bound * 0.999), 0.5, 0.05);
    EXPECT_LT(boxHeightAfterFall(bound * 1.001), -1.0);
}

TEST(PluginPrecision, AHeavyBodyIsNamedWithItsMassAndTheRemedy) {
    test::TestWorld w;
    Plugin plugin(w.world);
    plugin.addVisualBody(boxMesh("light", 0.5), {}, at(1));
    EXPECT_TRUE(plugin.takeWarnings().empty());
    plugin.addVisualBody(boxMesh("statue", 0.5, 2.0e7), {}, at(3)); // 2e7 kg
    const auto warnings = plugin.takeWarnings();
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_TRUE(mentions(warnings, "body 'statue': mass 2e+07 kg"));
    EXPECT_TRUE(mentions(warnings, "--units"));
    EXPECT_TRUE(plugin.takeWarnings().empty()); // the queue was emptied
}

TEST(PluginPrecision, StaticBodiesMayBeAsHeavyAsTheyLike) {
    test::TestWorld w;
    Plugin plugin(w.world);
    BodySettings fixed;
    fixed.dynamic = false;
    plugin.addVisualBody(boxMesh("mountain", 0.5, 1.0e9), fixed, at(0));
    EXPECT_TRUE(plugin.takeWarnings().empty());
}

TEST(PluginPrecision, BodiesSmallerThanTheContactMarginsOrLargerThanAKilometreAreNamed) {
    test::TestWorld w;
    Plugin plugin(w.world);
    plugin.addVisualBody(boxMesh("bead", 0.002), {}, at(1)); // 4 mm
    plugin.addVisualBody(boxMesh("moon", 800, 1.0), {}, at(2000)); // 1.6 km
    const auto warnings = plugin.takeWarnings();
    EXPECT_TRUE(mentions(warnings, "body 'bead': its smallest size 0.004 m is below 0.01 m"));
    EXPECT_TRUE(mentions(warnings, "body 'moon': its largest size 1.6e+03 m is above 1e+03 m"));
}

// A 1 kg application box resting on a 5,000 kg Shatter slab: one warning naming both, once.
TEST(PluginPrecision, AMassRatioAboveAThousandAtAContactIsNamedOnce) {
    test::TestWorld w;
    w.addGround();
    Plugin plugin(w.world);
    plugin.addVisualBody(boxMesh("slab", 0.5, 5000.0), {}, at(0.5));
    btBoxShape shape(btVector3(0.05f, 0.05f, 0.05f));
    btVector3 inertia;
    shape.calculateLocalInertia(1, inertia);
    btRigidBody pebble(1, nullptr, &shape, inertia);
    pebble.setWorldTransform(at(1.06));
    w.world.addRigidBody(&pebble);
    w.step(240 * 3);
    w.world.removeRigidBody(&pebble);
    const auto warnings = plugin.takeWarnings();
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_TRUE(mentions(warnings, "an application body (1 kg) touches body 'slab' (5e+03 kg)") ||
                mentions(warnings, "body 'slab' (5e+03 kg) touches an application body (1 kg)"));
}
