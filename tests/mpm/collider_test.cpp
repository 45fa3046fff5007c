// The static colliders of the MPM solver: the contact rule, and the box test the gather uses
// to skip colliders for whole chunks of particles (which must never skip a touching one).
#include <shatter/plugin/mpm/Collider.h>

#include <gtest/gtest.h>

#include <random>

namespace shatter::mpm {
namespace {

TEST(Collider, GroundStopsApproachKeepsSeparationAndAppliesFriction) {
    const HalfPlaneCollider ground(Vec2(0, 0), Vec2(0, 1));
    Vec2 v(3, -4);
    EXPECT_TRUE(ground.project(Vec2(1, -0.1), v));
    EXPECT_EQ(v, Vec2(3, 0)); // frictionless: the normal part goes, the tangential stays
    v = Vec2(3, 4);
    EXPECT_TRUE(ground.project(Vec2(1, -0.1), v));
    EXPECT_EQ(v, Vec2(3, 4)); // leaving: untouched
    v = Vec2(3, -4);
    EXPECT_FALSE(ground.project(Vec2(1, 0.1), v));
    EXPECT_EQ(v, Vec2(3, -4)); // outside: untouched
    const HalfPlaneCollider rough(Vec2(0, 0), Vec2(0, 1), 0.5);
    v = Vec2(3, -4);
    rough.project(Vec2(1, -0.1), v);
    EXPECT_NEAR(v.x(), 1, 1e-12); // Coulomb: 0.5 · 4 m/s of tangential speed lost
    EXPECT_EQ(v.y(), 0);
    v = Vec2(1, -4);
    rough.project(Vec2(1, -0.1), v);
    EXPECT_EQ(v, Vec2(0, 0)); // sticks
}

// mayTouch(box) must be true whenever a point of the box is inside (signedDistance <= 0):
// checked on a lattice of points over random boxes, including their corners and edges, for
// boxes near, across and inside each collider's surface. It must also say false for a box
// that is clearly away, or the chunks would not skip anything.
void checkMayTouch(const Collider& c, const Box& away) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> corner(-3, 3), size(0, 1.5);
    int touching = 0, skipped = 0;
    for (int k = 0; k < 2000; ++k) {
        const Vec2 lo(corner(rng), corner(rng));
        const Box box{lo, lo + Vec2(size(rng), size(rng))};
        bool inside = false;
        for (int i = 0; i <= 8; ++i)
            for (int j = 0; j <= 8; ++j) {
                const Vec2 p = box.min + (box.max - box.min).cwiseProduct(Vec2(i / 8.0, j / 8.0));
                inside = inside || c.signedDistance(p) <= 0;
            }
        if (inside) {
            ASSERT_TRUE(c.mayTouch(box)) << box.min.transpose() << " / " << box.max.transpose();
            ++touching;
        } else if (!c.mayTouch(box)) {
            ++skipped;
        }
    }
    EXPECT_GT(touching, 100);
    EXPECT_GT(skipped, 100);
    EXPECT_FALSE(c.mayTouch(away));
}

TEST(Collider, BoxTestNeverSkipsATouchingCollider) {
    const Box away{Vec2(10, 10), Vec2(11, 11)};
    checkMayTouch(HalfPlaneCollider(Vec2(0.3, -0.2), Vec2(1, 2)), away);
    checkMayTouch(BoxCollider(Box{Vec2(-1, -0.5), Vec2(0.7, 1.2)}), away);
    checkMayTouch(CircleCollider(Vec2(0.2, 0.1), 1.3), away);
}

} // namespace
} // namespace shatter::mpm
