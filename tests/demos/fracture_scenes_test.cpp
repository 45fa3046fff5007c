// The fracture scenes of the demos and their benchmark (demos/FractureScenes.h).
#include "demos/FractureScenes.h"

#include <shatter/bullet_ext/Plugin.h>
#include <shatter/bullet_ext/VisualBody.h>
#include <shatter/bullet_ext/shape/FragmentHull.h>

#include <gtest/gtest.h>

namespace shatter::demo {
namespace {

// The glass shards are the pane's slab cut by convex cells: each collides as its hull (issue
// 16: as group shapes, the shards touching along every crack held about 1,900 contact points
// a step, four times as many as their hulls). Only the rest of the pane, which keeps the
// hinges, and its islands stay group shapes.
TEST(GlassScene, EveryShardCollidesAsItsHull) {
    Scene scene(1);
    FractureSummary summary(scene);
    buildGlassScene(scene, GlassScene{}, summary);
    for (int f = 1; f <= 10 && summary.events() == 0; ++f) {
        scene.world().stepSimulation(btScalar(1.0 / 60), 4, btScalar(1.0 / 240));
        summary.frame({f, 10, f / 60.0, scene.plugin().takeEvents()});
    }
    ASSERT_EQ(summary.events(), 1);
    int hulls = 0, others = 0;
    for (const auto& body : scene.plugin().bodies()) {
        if (body->rigidBody().getInvMass() == 0) continue;
        if (isFragmentHull(body->rigidBody().getCollisionShape()))
            ++hulls;
        else
            ++others;
    }
    EXPECT_EQ(hulls, 54);
    // The rest of the pane, which keeps the hinges, and an island of 12 quads the cut left
    // attached to the rest: islands of the rest are not proved clear of the rest.
    EXPECT_EQ(others, 2);
}

} // namespace
} // namespace shatter::demo
