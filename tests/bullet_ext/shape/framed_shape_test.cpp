// FramedShape remembers its angular motion disc: after every kind of edit it gives, bit for
// bit, what a plain btCompoundShape with the same edits computes.
#include <shatter/bullet_ext/shape/FramedShape.h>
#include "tests/support/SameBits.h"

#include <BulletCollision/CollisionShapes/btBoxShape.h>
#include <BulletCollision/CollisionShapes/btSphereShape.h>
#include <gtest/gtest.h>

#include <string>

namespace shatter {
namespace {

using shatter::test::sameBits;

btTransform placed(float x, float y, float z, float turn) {
    return btTransform(btQuaternion(btVector3(1, 2, 3).normalized(), turn), btVector3(x, y, z));
}

// A compound with children of its own (setLocalScaling scales its children).
struct Side {
    explicit Side(btCompoundShape& c) : compound(c) {}
    btCompoundShape& compound; // through the base, as Bullet's own code would edit it
    btBoxShape box{btVector3(0.3f, 0.5f, 0.7f)};
    btSphereShape sphere{0.4f};
};

// The same edits on a FramedShape and on Bullet's own compound, compared after each.
struct FramedAndPlain {
    FramedShape framed;
    btCompoundShape plain{/*enableDynamicAabbTree=*/false, 1};
    Side a{framed}, b{plain};
    int edits = 0;

    template <typename Edit>
    void edit(const Edit& e) {
        SCOPED_TRACE("edit " + std::to_string(++edits));
        e(a);
        e(b);
        expectSame();
    }
    void expectSame() const {
        EXPECT_TRUE(sameBits(framed.getAngularMotionDisc(), plain.getAngularMotionDisc()))
            << framed.getAngularMotionDisc() << " " << plain.getAngularMotionDisc();
        EXPECT_TRUE(sameBits(framed.getContactBreakingThreshold(0.02f), plain.getContactBreakingThreshold(0.02f)));
    }
};

TEST(FramedShape, GivesBulletsDiscAfterEveryEdit) {
    FramedAndPlain p;
    p.expectSame(); // no children
    p.edit([](Side& s) { s.compound.addChildShape(placed(0.1f, -0.2f, 0.3f, 0.4f), &s.box); });
    p.edit([](Side& s) { s.compound.recalculateLocalAabb(); });
    p.edit([](Side& s) { s.compound.setMargin(0.01f); });
    p.edit([](Side& s) { s.compound.updateChildTransform(0, placed(-0.5f, 0.25f, 1.5f, 1.1f)); });
    p.edit([](Side& s) { s.compound.updateChildTransform(0, placed(2.0f, 0.0f, 0.0f, 0.2f), false); });
    p.edit([](Side& s) { s.compound.addChildShape(placed(1.0f, 1.0f, -1.0f, 0.0f), &s.sphere); });
    p.edit([](Side& s) { s.compound.setLocalScaling(btVector3(1.5f, 0.5f, 2.0f)); });
    p.edit([](Side& s) { s.compound.removeChildShapeByIndex(1); });
    p.edit([](Side& s) { s.compound.removeChildShape(&s.box); }); // none left
    p.edit([](Side& s) { s.compound.addChildShape(placed(0.0f, 3.0f, 0.0f, 2.0f), &s.box); });
}

TEST(FramedShape, ChildChangedOnItsOwnKeepsTheBoxBulletKeeps) {
    // A child that changes without the compound being told leaves Bullet's local box as it was;
    // the remembered disc is that box's, as Bullet's is.
    FramedAndPlain p;
    p.edit([](Side& s) {
        s.compound.addChildShape(placed(0.1f, 0.2f, 0.3f, 0.4f), &s.box);
        s.compound.recalculateLocalAabb();
    });
    p.edit([](Side& s) { s.box.setMargin(0.2f); });
    p.edit([](Side& s) { s.compound.recalculateLocalAabb(); });
}

} // namespace
} // namespace shatter
