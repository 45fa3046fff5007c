// Fragments fall asleep by the speed of their points, not by Bullet's angular threshold for
// bodies of a metre (bullet_ext/SleepingThreshold.h): the shards of a broken closed mesh
// (Spot the cow) turned in place at 1-30 rad/s with their centres at 1-15 cm/s for 10 s, so
// no island of the heap ever slept.
#include <shatter/bullet_ext/Plugin.h>
#include <shatter/bullet_ext/VisualBody.h>
#include <shatter/bullet_ext/fracture/FractureSystem.h>
#include "tests/bullet_ext/fracture/FractureFixtures.h"
#include "tests/support/TestWorld.h"

#include <gtest/gtest.h>

namespace shatter {
namespace {

// A 4 cm cube broken off as a fragment of its own, floating without gravity and turning about
// a face normal at `spin` rad/s; whether it is asleep 3 s later. Its corners lie
// 0.02 × √3 = 3.46 cm from its centre.
bool turningShardSleeps(double spin) {
    test::TestWorld w;
    w.world.setGravity(btVector3(0, 0, 0));
    Plugin plugin(w.world);
    BodySettings s;
    s.fracture.enabled = true;
    const auto mesh = test::cubeBlock("shard", 1, 1, 1, 0.04);
    VisualBody& body = plugin.addVisualBody(mesh, s, btTransform::getIdentity());
    const auto fragments = plugin.fractures().replace(body, test::partition(mesh, {0}), -1);
    btRigidBody& shard = fragments.at(0)->rigidBody();
    shard.setAngularVelocity(btVector3(0, btScalar(spin), 0));
    w.step(720);
    return !shard.isActive();
}

TEST(FragmentSleep, AShardSleepsWhenNoPointOfItMovesFasterThanTheLinearThreshold) {
    // Bullet's thresholds: 0.8 m/s, 1 rad/s. At 5 rad/s the corners move at 17 cm/s: slow for
    // a shard, though 5 times Bullet's angular threshold (awake for ever before the fix).
    EXPECT_TRUE(turningShardSleeps(5.0));
    // At 30 rad/s the corners move at 1.04 m/s: the shard stays awake.
    EXPECT_FALSE(turningShardSleeps(30.0));
}

} // namespace
} // namespace shatter
