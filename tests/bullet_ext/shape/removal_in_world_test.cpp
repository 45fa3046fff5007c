// Primitives removed from a group with its body left in the world (RemovalInWorld.h,
// LatticeSettings::keepPairsOnShrink): the pair with the floor keeps its algorithm, its leaf
// pairs and their manifolds (no fresh clip), no point is left on a removed primitive, and the
// kept points stay where they were in the world when the body's frame moves to its new centre,
// with their impulses (the solver's warm start).
#include "tests/bullet_ext/shape/group_scene.h"

#include <shatter/bullet_ext/RemovalInWorld.h>
#include <shatter/bullet_ext/shape/GroupShape.h>

#include <gtest/gtest.h>

#include <map>
#include <vector>

using namespace shatter;
using namespace shatter::test;

namespace {

// A point of the slab-floor pair: on which slab primitive, where in the world, how old, and
// the impulse the solver would start from.
struct Seen {
    int primitive;
    btVector3 world; // on the slab
    int lifeTime;
    btScalar impulse = 0;
};

// A slab of 3 × 3 boxes in a compound (as VisualBody frames its group) resting on a floor of
// 6 × 6; the slab loses its primitives 0 and 4 and its frame moves, in the world or out of it.
struct Slab {
    GroupWorld w;
    GroupShape* group = nullptr;
    btCompoundShape* compound = nullptr;
    btRigidBody* slab = nullptr;
    btRigidBody* floor = nullptr;

    Slab() {
        const BodyFrame f = toBodyFrame(slabFloor(3, 3, 0.1));
        group = &w.keep(std::make_unique<GroupShape>(f.primitives, 0.004));
        auto framed = std::make_unique<btCompoundShape>(false, 1);
        framed->addChildShape(btTransform::getIdentity(), group);
        compound = framed.get();
        floor = w.addStaticGroup(slabFloor(6, 6, 0.1));
        const btTransform pose(btQuaternion(btVector3(1, 0, 1).normalized(), 0.02f), btVector3(0.02f, 0.21f, 0.03f));
        const btVector3 inertia = f.inertia;
        slab = w.add(std::move(framed), f.mass, pose * f.bodyToDesign, &inertia);
        w.step(120);
    }

    // Calls f(point, slabIsBody0) for every point of the slab's manifolds.
    template <class F>
    void eachPoint(F f) {
        for (int m = 0; m < w.dispatcher().getNumManifolds(); ++m) {
            const btPersistentManifold* manifold = w.dispatcher().getManifoldByIndexInternal(m);
            const bool side0 = manifold->getBody0() == slab;
            if (!side0 && manifold->getBody1() != slab) continue;
            for (int k = 0; k < manifold->getNumContacts(); ++k) f(manifold->getContactPoint(k), side0);
        }
    }

    // Every point of the slab-floor manifolds.
    std::vector<Seen> points() {
        std::vector<Seen> out;
        eachPoint([&](const btManifoldPoint& p, bool side0) {
            out.push_back({side0 ? p.m_index0 : p.m_index1, side0 ? p.getPositionWorldOnA() : p.getPositionWorldOnB(),
                           p.getLifeTime(), p.m_appliedImpulse});
        });
        return out;
    }

    // The same points where the body's frame places their local points now.
    std::vector<btVector3> placedByFrame() {
        std::vector<btVector3> out;
        eachPoint([&](const btManifoldPoint& p, bool side0) {
            out.push_back(slab->getWorldTransform() * (side0 ? p.m_localPointA : p.m_localPointB));
        });
        return out;
    }

    btCollisionAlgorithm* pairAlgorithm() {
        btBroadphasePair* pair = w.world().getPairCache()->findPair(slab->getBroadphaseHandle(), floor->getBroadphaseHandle());
        return pair ? pair->m_algorithm : nullptr;
    }

    // Removes primitives 0 and 4 and moves the body frame by `move` (in the old body frame), the
    // group staying where it is in the world (VisualBody::reframe). Returns the old frame.
    btTransform shrink(const btTransform& move) {
        const btTransform before = slab->getWorldTransform();
        group->removePrimitives({0, 4});
        compound->updateChildTransform(0, move.inverse() * compound->getChildTransform(0));
        const btTransform after = before * move;
        slab->setWorldTransform(after);
        slab->setInterpolationWorldTransform(after);
        return before;
    }
};

// Old primitive -> new one, for a removal of 0 and 4 among 9.
constexpr int kNewIndex[9] = {-1, 0, 1, 2, -1, 3, 4, 5, 6};

const btTransform kMove(btQuaternion(btVector3(0, 1, 0), 0.1f), btVector3(0.03f, 0.0f, -0.02f));

} // namespace

TEST(RemovalInWorld, TheGroupPairKeepsItsLeavesAndTheirPointsFollowTheRemovalAndTheNewFrame) {
    Slab s;
    const std::vector<Seen> before = s.points();
    btCollisionAlgorithm* algorithm = s.pairAlgorithm();
    ASSERT_NE(algorithm, nullptr);
    std::vector<Seen> kept; // the points on primitives that stay, with their new indices
    for (const Seen& p : before) {
        ASSERT_GE(p.primitive, 0);
        ASSERT_LT(p.primitive, 9);
        if (kNewIndex[p.primitive] >= 0) kept.push_back({kNewIndex[p.primitive], p.world, p.lifeTime, p.impulse});
    }
    ASSERT_GT(kept.size(), 8u);
    btScalar carried = 0; // by the kept points
    for (const Seen& p : kept) carried += p.impulse;
    ASSERT_GT(carried, 0) << "the slab rests on the floor's points";
    ASSERT_LT(kept.size(), before.size()) << "some points must lie on the removed primitives";

    const btTransform old = s.shrink(kMove);
    followRemoval(s.w.dispatcher(), *s.slab, s.group->indexMapFrom(s.group->revision() - 1), old);
    s.w.world().updateSingleAabb(s.slab);

    // Only the kept points, renumbered, where they were: by their world positions and by their
    // local points in the new frame.
    const std::vector<Seen> now = s.points();
    const std::vector<btVector3> placed = s.placedByFrame();
    ASSERT_EQ(now.size(), kept.size());
    std::multimap<int, btVector3> expected;
    for (const Seen& p : kept) expected.emplace(p.primitive, p.world);
    for (size_t k = 0; k < now.size(); ++k) {
        ASSERT_GE(now[k].primitive, 0);
        ASSERT_LT(now[k].primitive, 7);
        EXPECT_LT((placed[k] - now[k].world).length(), 1e-5f) << "point " << k << " moved with the frame";
        bool found = false;
        const auto [first, last] = expected.equal_range(now[k].primitive);
        for (auto it = first; it != last; ++it) found |= (it->second - now[k].world).length() < 1e-6f;
        EXPECT_TRUE(found) << "point " << k << " on primitive " << now[k].primitive;
    }
    btScalar still = 0; // the kept points' impulses, for the solver's warm start
    for (const Seen& p : now) still += p.impulse;
    EXPECT_NEAR(still, carried, 1e-5f * carried);

    // The next step runs the same pair algorithm and the same manifolds: every kept point is
    // still there, old (no fresh clip makes new manifolds), each leaf's points on one primitive.
    s.w.step(1);
    EXPECT_EQ(s.pairAlgorithm(), algorithm);
    int old_points = 0;
    for (const Seen& p : s.points()) {
        EXPECT_LT(p.primitive, 7);
        if (p.lifeTime > 100) ++old_points;
    }
    EXPECT_EQ(old_points, int(kept.size()));
    for (int m = 0; m < s.w.dispatcher().getNumManifolds(); ++m) {
        const btPersistentManifold* manifold = s.w.dispatcher().getManifoldByIndexInternal(m);
        const bool side0 = manifold->getBody0() == s.slab;
        if (!side0 && manifold->getBody1() != s.slab) continue;
        for (int k = 1; k < manifold->getNumContacts(); ++k) {
            const auto index = [&](int q) { return side0 ? manifold->getContactPoint(q).m_index0 : manifold->getContactPoint(q).m_index1; };
            EXPECT_EQ(index(k), index(0)) << "a leaf manifold holds one primitive's points";
        }
    }

    // It rests on: the points stood where the body is.
    const btVector3 centre = s.slab->getCenterOfMassPosition();
    s.w.step(120);
    EXPECT_LT((s.slab->getCenterOfMassPosition() - centre).length(), 1e-3f);
    EXPECT_LT(s.slab->getLinearVelocity().length(), 1e-2f);
}

TEST(RemovalInWorld, OutOfTheWorldThePairAndItsPointsAreMadeAnew) {
    // The control: the same shrink with the body out of the world leaves no old point.
    Slab s;
    s.w.world().removeRigidBody(s.slab);
    s.shrink(kMove);
    s.w.world().addRigidBody(s.slab);
    s.w.step(1);
    ASSERT_FALSE(s.points().empty());
    for (const Seen& p : s.points()) EXPECT_LE(p.lifeTime, 1);
}

TEST(RemovalInWorld, AShapeTellsWhereItsPrimitivesWentThroughAChainOfRemovals) {
    const BodyFrame f = toBodyFrame(slabFloor(3, 3, 0.1));
    GroupShape g(f.primitives, 0.004);
    const std::uint64_t start = g.revision();
    EXPECT_FALSE(g.renumberedSince(start));
    EXPECT_TRUE(g.indexMapFrom(start).empty());
    g.removePrimitives({0, 4});
    EXPECT_TRUE(g.renumberedSince(start));
    EXPECT_EQ(g.indexMapFrom(start), (std::vector<int>{-1, 0, 1, 2, -1, 3, 4, 5, 6}));
    g.removePrimitives({1});
    EXPECT_EQ(g.indexMapFrom(start), (std::vector<int>{-1, 0, -1, 1, -1, 2, 3, 4, 5}));
    EXPECT_EQ(g.indexMapFrom(start + 1), (std::vector<int>{0, -1, 1, 2, 3, 4, 5}));
    EXPECT_TRUE(g.indexMapFrom(g.revision()).empty());
    // Primitives added: no map across it.
    g.removePrimitives({0}, {f.primitives[0]});
    EXPECT_TRUE(g.indexMapFrom(start).empty());
    EXPECT_TRUE(g.renumberedSince(start + 2));
}
