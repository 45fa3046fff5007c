// Contacts solved in their own order (OrderedContacts.h, HullPairContacts::contactOrder):
// the order does not depend on where the manifolds lie in the dispatcher, so a group pair's
// empty leaf manifolds can go (keepEmptyLeafManifolds off) without changing a bit; a stack
// still rests; the Plugin puts its solver in front of the world's when asked and takes it out
// again; a world it cannot wrap stays in Bullet's order with its empty manifolds where the
// own order was asked for only where possible, and is an error where it was required (a
// multi-threaded world too); one Plugin per world; the application's dispatcher flags do not
// touch the order, and replacing the world's solver returns it to Bullet's order.
#include "tests/bullet_ext/shape/group_scene.h"
#include "tests/bullet_ext/shape/scoped_contact_settings.h"

#include <shatter/bullet_ext/AttachedWorld.h>
#include <shatter/bullet_ext/OrderedContacts.h>
#include <shatter/bullet_ext/Plugin.h>
#include <shatter/bullet_ext/shape/HullPairContacts.h>
#include <shatter/plugin/common/InputError.h>

#include <BulletDynamics/ConstraintSolver/btSequentialImpulseConstraintSolverMt.h>
#include <BulletDynamics/Dynamics/btDiscreteDynamicsWorldMt.h>
#include <BulletDynamics/Featherstone/btMultiBodyConstraintSolver.h>
#include <BulletDynamics/Featherstone/btMultiBodyDynamicsWorld.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

namespace shatter {
namespace {

using test::GroupWorld;

btTransform pose(double angle, double x, double y, double z) {
    return btTransform(btQuaternion(btVector3(1, 2, 3).normalized(), btScalar(angle)), btVector3(btScalar(x), btScalar(y), btScalar(z)));
}

using Order = HullPairContacts::ContactOrder;

// A world whose solver takes the contacts in their own order if `ordered`, as the Plugin sets
// it up (else the wrapper passes them on as they come, as in a world the Plugin cannot wrap).
struct OrderedWorld {
    GroupWorld w;
    OrderedContactSolver solver{*w.world().getConstraintSolver()};
    AttachedWorld attached{w.dispatcher()};
    explicit OrderedWorld(bool ordered) {
        w.world().setConstraintSolver(&solver);
        attached.setContactsOrdered(ordered);
    }
    ~OrderedWorld() { w.world().setConstraintSolver(&solver.inner()); }
};

// Six L shapes dropped turned onto a slab floor (a static group) pile up, 1.5 s: every body's
// final state, and how many manifolds the dispatcher holds at the end.
struct Pile {
    std::vector<btScalar> state;
    int manifolds = 0;
    int manifoldsWithPoints = 0;
};
Pile pileOfLs(const HullPairContacts& settings, bool ordered) {
    const test::ScopedContactSettings scope(settings);
    OrderedWorld o(ordered);
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
    HullPairContacts keep, drop; // drop: the defaults
    keep.keepEmptyLeafManifolds = true;
    const Pile a = pileOfLs(keep, true), b = pileOfLs(drop, true);
    ASSERT_EQ(a.state.size(), b.state.size());
    for (size_t k = 0; k < a.state.size(); k += 9) EXPECT_GT(a.state[k + 3], 0.0f) << "every L lies on the floor or another L";
    for (size_t i = 0; i < a.state.size(); ++i) EXPECT_EQ(a.state[i], b.state[i]) << "component " << i;
    EXPECT_EQ(a.manifoldsWithPoints, b.manifoldsWithPoints);
    EXPECT_GT(a.manifolds, a.manifoldsWithPoints + 10) << "the pile should hold empty leaf manifolds";
    EXPECT_EQ(b.manifolds, b.manifoldsWithPoints) << "every leaf manifold left should hold points";
}

TEST(OrderedContacts, WithoutTheOrderEmptyLeafManifoldsStay) {
    // In a world whose contacts are in Bullet's order (the default, or one the Plugin could not
    // wrap) an empty manifold's place still orders the solve: they are kept although the
    // settings say not to, and the world gives the bits of keeping them by request.
    HullPairContacts keep, drop; // drop: the defaults
    keep.keepEmptyLeafManifolds = true;
    const Pile a = pileOfLs(keep, false), b = pileOfLs(drop, false);
    EXPECT_GT(a.manifolds, a.manifoldsWithPoints + 10) << "the pile should hold empty leaf manifolds";
    EXPECT_EQ(a.manifolds, b.manifolds);
    for (size_t i = 0; i < a.state.size(); ++i) EXPECT_EQ(a.state[i], b.state[i]) << "component " << i;
}

// test::stackOfBoxes with these contact settings.
test::BoxStack stackOfBoxes(const HullPairContacts& settings, bool ordered) {
    const test::ScopedContactSettings scope(settings);
    OrderedWorld o(ordered);
    return test::stackOfBoxes(o.w);
}

TEST(OrderedContacts, AStackRestsWhereAndAsStillAsInBulletsOrder) {
    // own: drops empty leaf manifolds (keepEmptyLeafManifolds' default); the order is the
    // world's (`ordered`), not these settings' contactOrder, which only a Plugin reads.
    HullPairContacts bullets, own;
    bullets.keepEmptyLeafManifolds = true;
    const test::BoxStack a = stackOfBoxes(bullets, false), b = stackOfBoxes(own, true);
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

// With the settings `order`, a Plugin made and detached on `world`: whether it ordered the
// contacts, what solver the world had meanwhile and after, and the Plugin's warnings.
struct Attached {
    bool ordered = false;
    bool marked = false; // dispatcherOrdersContacts said so too
    btConstraintSolver* solverWhileAttached = nullptr; // the world's then (freed after, if the Plugin's)
    btConstraintSolver* wrapped = nullptr;             // the solver behind it, if the Plugin's
    btConstraintSolver* solverAfter = nullptr;
    bool markedAfter = false;
    std::vector<std::string> warnings;
};
Attached attach(btDiscreteDynamicsWorld& world, Order order) {
    HullPairContacts settings = hullPairContacts();
    settings.contactOrder = order;
    const test::ScopedContactSettings scope(settings);
    Attached a;
    {
        Plugin plugin(world);
        a.ordered = plugin.contactsOrdered();
        a.marked = dispatcherOrdersContacts(world.getDispatcher());
        a.solverWhileAttached = world.getConstraintSolver();
        if (auto* ordered = dynamic_cast<OrderedContactSolver*>(a.solverWhileAttached)) a.wrapped = &ordered->inner();
        world.stepSimulation(btScalar(1.0 / 60), 1, btScalar(1.0 / 60));
        a.warnings = plugin.takeWarnings();
    }
    a.solverAfter = world.getConstraintSolver();
    a.markedAfter = dispatcherOrdersContacts(world.getDispatcher());
    return a;
}

TEST(OrderedContacts, ThePluginPutsItsSolverInFrontOfTheWorldsWhenAskedAndTakesItOut) {
    test::TestWorld w;
    for (const Order order : {Order::OwnWherePossible, Order::Own}) {
        const Attached a = attach(w.world, order);
        EXPECT_TRUE(a.ordered);
        EXPECT_TRUE(a.marked);
        EXPECT_EQ(a.wrapped, &w.solver);
        EXPECT_EQ(a.solverAfter, &w.solver);
        EXPECT_FALSE(a.markedAfter) << "detach returns the world to Bullet's order";
        EXPECT_TRUE(a.warnings.empty());
    }
    const Attached bullets = attach(w.world, Order::Bullets); // the default: the application keeps its own solver
    EXPECT_FALSE(bullets.ordered);
    EXPECT_FALSE(bullets.marked);
    EXPECT_EQ(bullets.solverWhileAttached, &w.solver);
    EXPECT_EQ(bullets.wrapped, nullptr);
    EXPECT_TRUE(bullets.warnings.empty()) << "Bullet's order was asked for";
    EXPECT_EQ(HullPairContacts{}.contactOrder, Order::Bullets);
}

TEST(OrderedContacts, AWorldThatMadeItsOwnSolverStaysInBulletsOrderUnlessTheOwnOrderIsRequired) {
    // A world that made its own solver frees it itself, so it cannot be wrapped.
    btDefaultCollisionConfiguration config;
    btCollisionDispatcher dispatcher(&config);
    btDbvtBroadphase broadphase;
    btDiscreteDynamicsWorld owning(&dispatcher, &broadphase, nullptr, &config);
    btConstraintSolver* own = owning.getConstraintSolver();
    const Attached a = attach(owning, Order::OwnWherePossible);
    EXPECT_FALSE(a.ordered);
    EXPECT_FALSE(a.marked) << "its leaf pairs keep their empty manifolds";
    EXPECT_EQ(a.solverWhileAttached, own);
    ASSERT_EQ(a.warnings.size(), 1u);
    EXPECT_NE(a.warnings[0].find("Bullet's order"), std::string::npos) << a.warnings[0];
    EXPECT_NE(a.warnings[0].find("made its own solver"), std::string::npos) << a.warnings[0];
    EXPECT_THROW(attach(owning, Order::Own), InputError);
    EXPECT_EQ(owning.getConstraintSolver(), own);
    EXPECT_FALSE(dispatcherOrdersContacts(&dispatcher));
}

TEST(OrderedContacts, AMultiBodyWorldKeepsItsSolverAndSteps) {
    // btMultiBodyDynamicsWorld casts the world's solver by the type it reports: a wrapper
    // reporting its inner solver's type would be cast to a btMultiBodyConstraintSolver.
    btDefaultCollisionConfiguration config;
    btCollisionDispatcher dispatcher(&config);
    btDbvtBroadphase broadphase;
    btMultiBodyConstraintSolver solver;
    btMultiBodyDynamicsWorld world(&dispatcher, &broadphase, &solver, &config);
    for (const Order order : {Order::OwnWherePossible, Order::Bullets}) {
        const Attached a = attach(world, order);
        EXPECT_FALSE(a.ordered);
        EXPECT_FALSE(a.marked);
        EXPECT_EQ(a.solverWhileAttached, &solver);
        EXPECT_EQ(a.warnings.size(), order == Order::OwnWherePossible ? 1u : 0u);
    }
    EXPECT_THROW(attach(world, Order::Own), InputError); // not a sequential-impulse solver
    EXPECT_EQ(world.getConstraintSolver(), &solver);
}

TEST(OrderedContacts, AMultiThreadedWorldStaysInBulletsOrderUnlessTheOwnOrderIsRequired) {
    // Its island manager solves large islands with the world's multi-threaded solver, not the
    // one a wrapper would stand in front of (here: every island, as a large one would be).
    btDefaultCollisionConfiguration config;
    btCollisionDispatcher dispatcher(&config); // the distribution's btCollisionDispatcherMt crashes when made
    btDbvtBroadphase broadphase;
    btConstraintSolver* pooled[1] = {new btSequentialImpulseConstraintSolver}; // the pool deletes it
    btConstraintSolverPoolMt pool(pooled, 1);
    btSequentialImpulseConstraintSolverMt solverMt;
    btDiscreteDynamicsWorldMt world(&dispatcher, &broadphase, &pool, &solverMt, &config);
    const Attached a = attach(world, Order::OwnWherePossible);
    EXPECT_FALSE(a.ordered);
    EXPECT_FALSE(a.marked);
    EXPECT_EQ(a.solverWhileAttached, &pool);
    ASSERT_EQ(a.warnings.size(), 1u);
    EXPECT_NE(a.warnings[0].find("multi-threaded"), std::string::npos) << a.warnings[0];
    EXPECT_THROW(attach(world, Order::Own), InputError);
    EXPECT_EQ(world.getConstraintSolver(), &pool);
    EXPECT_TRUE(attach(world, Order::Bullets).warnings.empty());
}

// A cube of half size `half` for the Plugin's bodies.
geometry::PhysicalMesh orderedTestCube(double half) {
    std::vector<Eigen::Vector3d> v;
    for (int i = 0; i < 8; ++i) v.emplace_back(i & 1 ? half : -half, i & 2 ? half : -half, i & 4 ? half : -half);
    const std::vector<std::vector<int>> f = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    return geometry::buildPhysicalMesh("cube", v, f);
}

TEST(OrderedContacts, ASecondPluginOnAWorldThrowsAndLeavesTheFirstAsItWas) {
    for (const Order order : {Order::Own, Order::Bullets}) {
        HullPairContacts settings = hullPairContacts();
        settings.contactOrder = order;
        const test::ScopedContactSettings scope(settings);
        test::TestWorld w;
        w.addGround();
        const int flags = w.dispatcher.getDispatcherFlags();
        {
            Plugin first(w.world);
            btConstraintSolver* solver = w.world.getConstraintSolver();
            VisualBody& cube = first.addVisualBody(orderedTestCube(0.1), {}, test::at(0, 0.5, 0));
            try {
                Plugin second(w.world);
                ADD_FAILURE() << "a second Plugin on the world";
            } catch (const InputError& e) {
                EXPECT_NE(std::string(e.what()).find("already has a shatter::Plugin attached"), std::string::npos) << e.what();
            }
            EXPECT_EQ(w.world.getConstraintSolver(), solver);
            EXPECT_EQ(first.contactsOrdered(), order == Order::Own);
            EXPECT_EQ(dispatcherOrdersContacts(&w.dispatcher), order == Order::Own);
            EXPECT_EQ(w.dispatcher.getDispatcherFlags(), flags) << "the Plugin leaves Bullet's flags alone";
            w.step(240); // the first Plugin's cube still collides with the group algorithms it registered
            EXPECT_NEAR(cube.rigidBody().getCenterOfMassPosition().y(), 0.1, 0.01);
        }
        EXPECT_EQ(w.world.getConstraintSolver(), &w.solver);
        EXPECT_FALSE(dispatcherOrdersContacts(&w.dispatcher));
        Plugin again(w.world); // the first one's claim ended with it
        EXPECT_EQ(again.contactsOrdered(), order == Order::Own);
    }
}

TEST(OrderedContacts, TheApplicationsDispatcherFlagsLeaveTheOrderAlone) {
    // Bullet's samples set the flags outright: the order is Shatter's record, not a flag bit.
    HullPairContacts settings = hullPairContacts();
    settings.contactOrder = Order::Own;
    const test::ScopedContactSettings scope(settings);
    test::TestWorld w;
    const int flags = w.dispatcher.getDispatcherFlags();
    Plugin plugin(w.world);
    EXPECT_EQ(w.dispatcher.getDispatcherFlags(), flags);
    w.dispatcher.setDispatcherFlags(btCollisionDispatcher::CD_DISABLE_CONTACTPOOL_DYNAMIC_ALLOCATION);
    w.step(1);
    EXPECT_TRUE(plugin.contactsOrdered());
    EXPECT_TRUE(dispatcherOrdersContacts(&w.dispatcher));
    EXPECT_TRUE(plugin.takeWarnings().empty());
    w.dispatcher.setDispatcherFlags(flags);
}

TEST(OrderedContacts, ReplacingTheWorldsSolverReturnsItToBulletsOrderWithAWarning) {
    HullPairContacts settings = hullPairContacts();
    settings.contactOrder = Order::Own;
    const test::ScopedContactSettings scope(settings);
    test::TestWorld w;
    btSequentialImpulseConstraintSolver other;
    {
        Plugin plugin(w.world);
        btConstraintSolver* wrapper = w.world.getConstraintSolver();
        w.world.setConstraintSolver(&other);
        EXPECT_FALSE(plugin.contactsOrdered()) << "at once";
        w.step(1); // the Plugin notices in the step, and its group pairs keep empty manifolds from the next on
        EXPECT_FALSE(dispatcherOrdersContacts(&w.dispatcher));
        const std::vector<std::string> warnings = plugin.takeWarnings();
        ASSERT_EQ(warnings.size(), 1u);
        EXPECT_NE(warnings[0].find("solver was replaced"), std::string::npos) << warnings[0];
        w.world.setConstraintSolver(wrapper); // the application puts it back: still Bullet's order
        w.step(1);
        EXPECT_FALSE(plugin.contactsOrdered());
        EXPECT_FALSE(dispatcherOrdersContacts(&w.dispatcher));
        EXPECT_TRUE(plugin.takeWarnings().empty()) << "one warning";
        w.world.setConstraintSolver(&other);
    }
    EXPECT_EQ(w.world.getConstraintSolver(), &other) << "detach leaves the application's choice";
    w.world.setConstraintSolver(&w.solver);
}

} // namespace
} // namespace shatter
