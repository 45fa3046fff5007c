// A breaking wall with the contacts solved and snapshot in their own order
// (HullPairContacts::ContactOrder::Own) and no empty leaf manifolds: it breaks, and the pieces
// keep the wall's mass. (That freeing empty manifolds changes no bit is
// OrderedContacts.EmptyLeafManifoldsGoWithoutChangingABit: this small wall's pieces are
// lattice fragments, whose pairs keep their own algorithm.)
#include <shatter/bullet_ext/lattice/LatticeSystem.h>
#include <shatter/bullet_ext/shape/HullPairContacts.h>
#include "tests/bullet_ext/lattice/WallScene.h"
#include "tests/bullet_ext/shape/scoped_contact_settings.h"
#include "tests/support/PartsConserve.h"

#include <gtest/gtest.h>


namespace shatter {
namespace {

struct Broken {
    int links = 0;
    int pieces = 0;
};

Broken breakWall(const HullPairContacts& settings) {
    const test::ScopedContactSettings scope(settings);
    test::WallScene s(8.0);
    EXPECT_EQ(s.plugin.contactsOrdered(), settings.contactOrder != HullPairContacts::ContactOrder::Bullets);
    s.w.step(90);
    const LatticeBody& wall = *s.wall;
    EXPECT_NEAR(wall.currentMass(), wall.initialMass(), 1e-12 * wall.initialMass());
    const auto records = s.plugin.lattices().takeSplitRecords();
    EXPECT_FALSE(records.empty());
    for (const auto& r : records) {
        // Each split hands its mass and centre of mass on to its parts (the anchored wall's
        // splits start from rest: their momentum is zero on both sides).
        double mass = 0.0;
        Eigen::Vector3d moment = Eigen::Vector3d::Zero();
        for (const auto& part : r.parts) {
            mass += part.mass;
            moment += part.mass * part.centre;
        }
        EXPECT_NEAR(mass, r.parent.mass, 1e-12 * r.parent.mass);
        EXPECT_LT((moment / mass - r.parent.centre).norm(), 1e-9);
    }
    return {wall.brokenLinkCount(), wall.pieceCount()};
}

TEST(LatticeOrderedContacts, AWallBreaksAndItsPiecesKeepItsMass) {
    HullPairContacts own;
    own.contactOrder = HullPairContacts::ContactOrder::Own; // and no empty leaf manifolds (the default)
    const Broken b = breakWall(own);
    EXPECT_GT(b.links, 10);
    EXPECT_GT(b.pieces, 5) << "the wall should break into pieces";
}

} // namespace
} // namespace shatter
