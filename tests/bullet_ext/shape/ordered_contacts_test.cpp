// Contacts solved in their own order (OrderedContacts.h, HullPairContacts::orderedContacts):
// the order does not depend on where the manifolds lie in the dispatcher, so a group pair's
// empty leaf manifolds can go (keepEmptyLeafManifolds off) without changing a bit; a stack
// still rests; the Plugin puts its solver in front of the world's and takes it out again.
#include "tests/bullet_ext/shape/group_scene.h"
#include "tests/bullet_ext/shape/scoped_contact_settings.h"

#include <shatter/bullet_ext/OrderedContacts.h>
#include <shatter/bullet_ext/Plugin.h>
#include <shatter/bullet_ext/shape/HullPairContacts.h>
#include <shatter/plugin/common/InputError.h>

#include <BulletDynamics/Featherstone/btMultiBodyConstraintSolver.h>
#include <BulletDynamics/Featherstone/btMultiBodyDynamicsWorld.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

namespace shatter {
namespace {

using test::GroupWorld;

btTransform pose(double angle, double x, double y, double z) {
    return btTransform(btQuaternion(btVector3(1, 2, 3).normalized(), btScalar(angle)), btVector3(btScalar(x), btScalar(y), btScalar(z)));
}

// A world whose solver takes the contacts in their own order while the settings ask for it,
// as the Plugin sets it up.
struct OrderedWorld {
    GroupWorld w;
    OrderedContactSolver solver{*w.world().getConstraintSolver()};
    OrderedWorld() { w.world().setConstraintSolver(&solver); }
    ~OrderedWorld() { w.world().setConstraintSolver(&solver.inner()); }
};

// Six L shapes dropped turned onto a slab floor (a static group) pile up, 1.5 s: every body's
// final state, and how many manifolds the dispatcher holds at the end.
struct Pile {
    std::vector<btScalar> state;
    int manifolds = 0;
    int manifoldsWithPoints = 0;
};
Pile pileOfLs(const HullPairContacts& settings) {
    const test::ScopedContactSettings scope(settings);
    OrderedWorld o;
    GroupWorld& w = o.w;
    w.addStaticGroup(test::slabFloor(8, 8, 0.5));
    std::vector<btRigidBody*> bodies;
    for (int k = 0; k < 6; ++k)
        bodies.push_back(w.addGroup(test::lShape(), pose(0.7 * k, 0.05 * (k % 2), 0.15 + 0.18 * k, 0.04 * (k % 3)), 0.004));
    w.step(360);
    Pile p;
    for (const btRigidBody* b : bodies)
        for (int i = 0; i < 3; ++i) {
            p.state.push_back(b->getCenterOfMassPosition()[i]);
            p.state.push_back(b->getLinearVelocity()[i]);
            p.state.push_back(b->getAngularVelocity()[i]);
        }
    p.manifolds = w.dispatcher().getNumManifolds();
    for (int m = 0; m < p.manifolds; ++m) p.manifoldsWithPoints += w.dispatcher().getManifoldByIndexInternal(m)->getNumContacts() > 0;
    return p;
}

TEST(OrderedContacts, EmptyLeafManifoldsGoWithoutChangingABit) {
    HullPairContacts keep, drop;
    keep.orderedContacts = drop.orderedContacts = true;
    drop.keepEmptyLeafManifolds = false;
    const Pile a = pileOfLs(keep), b = pileOfLs(drop);
    ASSERT_EQ(a.state.size(), b.state.size());
    for (size_t k = 0; k < a.state.size(); k += 9) EXPECT_GT(a.state[k + 3], 0.0f) << "every L lies on the floor or another L";
    for (size_t i = 0; i < a.state.size(); ++i) EXPECT_EQ(a.state[i], b.state[i]) << "component " << i;
    EXPECT_EQ(a.manifoldsWithPoints, b.manifoldsWithPoints);
    EXPECT_GT(a.manifolds, a.manifoldsWithPoints + 10) << "the pile should hold empty leaf manifolds";
    EXPECT_EQ(b.manifolds, b.manifoldsWithPoints) << "every leaf manifold left should hold points";
}

TEST(OrderedContacts, WithoutTheOrderEmptyLeafManifoldsStay) {
    // Without orderedContacts an empty manifold's place still orders the solve: they are kept.
    HullPairContacts keep, drop;
    drop.keepEmptyLeafManifolds = false;
    const Pile a = pileOfLs(keep), b = pileOfLs(drop);
    EXPECT_EQ(a.manifolds, b.manifolds);
    for (size_t i = 0; i < a.state.size(); ++i) EXPECT_EQ(a.state[i], b.state[i]) << "component " << i;
}

// test::stackOfBoxes with these contact settings.
test::BoxStack stackOfBoxes(const HullPairContacts& settings) {
    const test::ScopedContactSettings scope(settings);
    OrderedWorld o;
    return test::stackOfBoxes(o.w);
}

TEST(OrderedContacts, AStackRestsWhereAndAsStillAsInBulletsOrder) {
    HullPairContacts bullets, own;
    own.orderedContacts = true;
    own.keepEmptyLeafManifolds = false;
    const test::BoxStack a = stackOfBoxes(bullets), b = stackOfBoxes(own);
    for (size_t k = 0; k < a.heights.size(); ++k) EXPECT_NEAR(b.heights[k], a.heights[k], 2e-4) << "box " << k;
    EXPECT_LT(a.fastest, 1e-3);
    EXPECT_LT(b.fastest, 1e-3) << "the stack must not jitter in the contacts' own order";
}

TEST(OrderedContacts, TheOrderIsTheManifoldsOwnWhereverTheyLie) {
    // Manifolds of two body pairs, several leaf pairs each, some empty: any arrangement of the
    // same manifolds gives the same order, by bodies and then by leaf pair, without the empty ones.
    btCollisionObject bodies[3];
    btBroadphaseProxy proxies[3];
    for (int i = 0; i < 3; ++i) {
        proxies[i].m_uniqueId = 10 - i; // ids in another order than the array's
        bodies[i].setBroadphaseHandle(&proxies[i]);
    }
    std::vector<btPersistentManifold> store;
    store.reserve(8);
    for (int k = 0; k < 8; ++k) {
        store.emplace_back(&bodies[k % 2], &bodies[2], 0, btScalar(0.02), btScalar(0.02));
        if (k % 3 == 2) continue; // empty
        btManifoldPoint p(btVector3(0, 0, 0), btVector3(0, 0, 0), btVector3(0, 1, 0), btScalar(-0.001));
        p.m_partId0 = -1;
        p.m_index0 = 7 - k;
        p.m_partId1 = -1;
        p.m_index1 = k / 2;
        store.back().addManifoldPoint(p);
    }
    std::vector<btPersistentManifold*> given;
    for (auto& m : store) given.push_back(&m);
    std::vector<btPersistentManifold*> first, again;
    orderContactManifolds(given.data(), int(given.size()), first);
    EXPECT_EQ(first.size(), 6u);
    for (size_t k = 1; k < first.size(); ++k) EXPECT_TRUE(contactPairBefore(first[k - 1], first[k])) << k;
    EXPECT_EQ(first.front()->getBody0(), &bodies[1]) << "the pair with the lower body id first";
    for (int turn = 1; turn < int(given.size()); ++turn) {
        std::rotate(given.begin(), given.begin() + 1, given.end());
        std::swap(given[0], given[turn]);
        orderContactManifolds(given.data(), int(given.size()), again);
        EXPECT_EQ(again, first) << "arrangement " << turn;
    }
    for (auto& b : bodies) b.setBroadphaseHandle(nullptr);
}

TEST(OrderedContacts, ThePluginPutsItsSolverInFrontOfTheWorldsOnlyWhenAskedAndTakesItOut) {
    test::TestWorld w;
    {
        Plugin plugin(w.world); // off (the default): the application keeps its own solver
        EXPECT_EQ(w.world.getConstraintSolver(), &w.solver);
    }
    HullPairContacts on = hullPairContacts();
    on.orderedContacts = true;
    const test::ScopedContactSettings ordering(on);
    {
        Plugin plugin(w.world);
        auto* ordered = dynamic_cast<OrderedContactSolver*>(w.world.getConstraintSolver());
        ASSERT_NE(ordered, nullptr);
        EXPECT_EQ(&ordered->inner(), &w.solver);
    }
    EXPECT_EQ(w.world.getConstraintSolver(), &w.solver);
    // A world that made its own solver frees it itself, so it cannot be wrapped: an error.
    btDefaultCollisionConfiguration config;
    btCollisionDispatcher dispatcher(&config);
    btDbvtBroadphase broadphase;
    btDiscreteDynamicsWorld owning(&dispatcher, &broadphase, nullptr, &config);
    btConstraintSolver* own = owning.getConstraintSolver();
    EXPECT_THROW(Plugin plugin(owning), InputError);
    EXPECT_EQ(owning.getConstraintSolver(), own);
}

TEST(OrderedContacts, AMultiBodyWorldKeepsItsSolverAndSteps) {
    // btMultiBodyDynamicsWorld casts the world's solver by the type it reports: a wrapper
    // reporting its inner solver's type would be cast to a btMultiBodyConstraintSolver.
    btDefaultCollisionConfiguration config;
    btCollisionDispatcher dispatcher(&config);
    btDbvtBroadphase broadphase;
    btMultiBodyConstraintSolver solver;
    btMultiBodyDynamicsWorld world(&dispatcher, &broadphase, &solver, &config);
    {
        Plugin plugin(world);
        EXPECT_EQ(world.getConstraintSolver(), &solver);
        world.stepSimulation(btScalar(1.0 / 60), 1, btScalar(1.0 / 60));
    }
    HullPairContacts on = hullPairContacts();
    on.orderedContacts = true;
    const test::ScopedContactSettings ordering(on);
    EXPECT_THROW(Plugin plugin(world), InputError); // not a sequential-impulse solver
    EXPECT_EQ(world.getConstraintSolver(), &solver);
}

} // namespace
} // namespace shatter
