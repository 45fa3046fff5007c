// Debris (LatticeSettings::debris): small loose fragments that collide with the ground, the
// wall and the ball but not with each other; their budget and lifetime remove the oldest first,
// with an event and the mass accounted for; the same seed gives the same bits.
#include <shatter/bullet_ext/lattice/LatticeBody.h>
#include <shatter/bullet_ext/lattice/LatticeSystem.h>
#include <shatter/bullet_ext/Plugin.h>
#include <shatter/bullet_ext/VisualBody.h>
#include <shatter/plugin/common/InputError.h>
#include <shatter/plugin/lattice/Fragments.h>
#include "tests/bullet_ext/lattice/WallScene.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <set>

namespace shatter {
namespace {

using test::WallScene;

// The test wall's single tets (of its jittered 10 cm cells) are 0.20-0.23 m across by
// lattice::pieceSize; 0.3 m takes them and pairs of them.
DebrisSettings debrisUpTo(double size = 0.3) {
    DebrisSettings d;
    d.maxSize = size;
    return d;
}

// A 200 kg ball at 8 m/s: 160-odd fragments within a second.
struct DebrisHit : WallScene {
    explicit DebrisHit(const DebrisSettings& debris, std::uint64_t seed = 1) : WallScene(8.0, seed, 200.0, debris) {}
};

std::set<const btCollisionObject*> debrisBodies(const LatticeBody& body) {
    std::set<const btCollisionObject*> out;
    for (const auto& p : body.pieces())
        if (p.debris) out.insert(&p.body->rigidBody());
    return out;
}

// Over a second after the ball hits: manifolds with points between two debris, and between a
// debris piece and the ground.
struct ContactsSeen {
    int debrisPairs = 0, debrisGround = 0, debris = 0;
};
ContactsSeen runAndWatch(DebrisHit& s) {
    ContactsSeen seen;
    for (int step = 0; step < 240; ++step) {
        s.w.step(1);
        const auto debris = debrisBodies(*s.wall);
        seen.debris = std::max(seen.debris, int(debris.size()));
        btDispatcher& d = *s.w.world.getDispatcher();
        for (int m = 0; m < d.getNumManifolds(); ++m) {
            const btPersistentManifold* manifold = d.getManifoldByIndexInternal(m);
            if (manifold->getNumContacts() == 0) continue;
            const bool a = debris.count(manifold->getBody0()), b = debris.count(manifold->getBody1());
            seen.debrisPairs += a && b;
            const btCollisionObject* ground = s.w.ground.get();
            seen.debrisGround += (a && manifold->getBody1() == ground) || (b && manifold->getBody0() == ground);
        }
    }
    return seen;
}

TEST(LatticeDebris, DebrisTouchTheGroundButNeverEachOther) {
    DebrisHit s(debrisUpTo());
    const ContactsSeen seen = runAndWatch(s);
    EXPECT_GT(seen.debris, 20);
    EXPECT_EQ(seen.debrisPairs, 0);
    EXPECT_GT(seen.debrisGround, 0);
    // Their pairs never reached the narrowphase: the broadphase holds none now.
    const auto debris = debrisBodies(*s.wall);
    btOverlappingPairCache& pairs = *s.w.world.getPairCache();
    for (int i = 0; i < pairs.getNumOverlappingPairs(); ++i) {
        const btBroadphasePair& p = pairs.getOverlappingPairArray()[i];
        EXPECT_FALSE(debris.count(static_cast<btCollisionObject*>(p.m_pProxy0->m_clientObject)) &&
                     debris.count(static_cast<btCollisionObject*>(p.m_pProxy1->m_clientObject)));
    }
    // None fell through the ground.
    for (const auto& p : s.wall->pieces()) {
        if (p.debris) {
            EXPECT_GT(p.body->rigidBody().getCenterOfMassPosition().y(), 0.0f);
        }
    }
    // Allowed to collide with each other, the same small pieces do.
    DebrisSettings colliding = debrisUpTo();
    colliding.collideWithEachOther = true;
    DebrisHit c(colliding);
    EXPECT_GT(runAndWatch(c).debrisPairs, 0);
}

TEST(LatticeDebris, OnlyFragmentsUpToTheSizeAreDebris) {
    DebrisHit s(debrisUpTo(0.21)); // some single tets are debris, some not
    s.w.step(120);
    int debris = 0, other = 0;
    for (const auto& p : s.wall->pieces()) {
        const double size = lattice::pieceSize(s.wall->lattice(), p.lattice.particles, p.mass.centerOfMass);
        EXPECT_EQ(p.debris, !p.lattice.anchored && size <= 0.21);
        (p.debris ? debris : other) += 1;
    }
    EXPECT_GT(debris, 0);
    EXPECT_GT(other, 0);
}

TEST(LatticeDebris, TheBudgetRemovesTheOldestFirstWithAnEventAndTheirMass) {
    DebrisSettings d = debrisUpTo();
    d.budget = 5;
    DebrisHit s(d);
    std::map<int, double> madeAt; // body id -> time its FragmentCreated event says
    std::vector<Event> expired;
    int removed = 0;
    for (int step = 0; step < 240; ++step) {
        s.w.step(1);
        EXPECT_LE(int(debrisBodies(*s.wall).size()), d.budget);
        for (const Event& e : s.plugin.takeEvents()) {
            if (e.type == EventType::FragmentCreated) madeAt[e.body] = e.time;
            if (e.type == EventType::DebrisExpired) expired.push_back(e);
            // Each expired piece then leaves the world.
            if (e.type == EventType::BodyRemoved && !expired.empty() && e.body == expired.back().body) ++removed;
        }
    }
    ASSERT_GT(expired.size(), 5u);
    EXPECT_EQ(removed, int(expired.size()));
    EXPECT_EQ(s.wall->removedDebrisCount(), int(expired.size()));
    // Oldest first: every piece removed was made no later than any debris piece still alive.
    double latestRemoved = 0.0;
    for (const Event& e : expired) {
        ASSERT_TRUE(madeAt.count(e.body));
        EXPECT_LE(madeAt[e.body], e.time);
        latestRemoved = std::max(latestRemoved, madeAt[e.body]);
    }
    for (const auto& p : s.wall->pieces()) {
        if (p.debris) {
            EXPECT_GE(p.madeAt, latestRemoved);
        }
    }
    // Removed mass is reported: what is left plus what was removed is the wall.
    EXPECT_GT(s.wall->removedDebrisMass(), 0.0);
    EXPECT_NEAR(s.wall->currentMass() + s.wall->removedDebrisMass(), s.wall->initialMass(), 1e-9 * s.wall->initialMass());
}

TEST(LatticeDebris, ALifetimeRemovesEachPieceOnceItHasLivedIt) {
    DebrisSettings d = debrisUpTo();
    d.lifetime = 0.1;
    DebrisHit s(d);
    std::map<int, double> madeAt;
    int expired = 0;
    for (int step = 0; step < 240; ++step) {
        s.w.step(1);
        for (const Event& e : s.plugin.takeEvents()) {
            if (e.type == EventType::FragmentCreated) madeAt[e.body] = e.time;
            if (e.type != EventType::DebrisExpired) continue;
            ++expired;
            ASSERT_TRUE(madeAt.count(e.body));
            EXPECT_GE(e.time - madeAt[e.body], d.lifetime - 1e-9);
            EXPECT_LT(e.time - madeAt[e.body], d.lifetime + 1.0 / 240 + 1e-9); // within the step it expired in
        }
    }
    EXPECT_GT(expired, 5);
    EXPECT_NEAR(s.wall->currentMass() + s.wall->removedDebrisMass(), s.wall->initialMass(), 1e-9 * s.wall->initialMass());
}

TEST(LatticeDebris, SameSeedGivesTheSameBits) {
    DebrisSettings d = debrisUpTo();
    d.budget = 20;
    DebrisHit a(d, 3), b(d, 3);
    a.w.step(120);
    b.w.step(120);
    ASSERT_EQ(a.wall->pieceCount(), b.wall->pieceCount());
    EXPECT_EQ(a.wall->removedDebrisCount(), b.wall->removedDebrisCount());
    for (int i = 0; i < a.wall->pieceCount(); ++i) {
        const auto& pa = a.wall->pieces()[i];
        const auto& pb = b.wall->pieces()[i];
        EXPECT_EQ(pa.lattice.particles, pb.lattice.particles);
        EXPECT_EQ(pa.debris, pb.debris);
        const btTransform& ta = pa.body->rigidBody().getWorldTransform();
        const btTransform& tb = pb.body->rigidBody().getWorldTransform();
        EXPECT_TRUE(ta.getOrigin() == tb.getOrigin() && ta.getBasis() == tb.getBasis()) << "piece " << i;
    }
}

TEST(LatticeDebris, BadSettingsAreAnErrorNamingTheBody) {
    DebrisSettings d;
    d.maxSize = -0.1;
    try {
        DebrisHit s(d);
        FAIL() << "no error";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("wall"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("debris max size"), std::string::npos) << e.what();
    }
}

} // namespace
} // namespace shatter
