// The cheaper contacts of group shapes (HullPairContacts.h): a cached separating face gives the
// same answer as searching every face; the group pair's reused primitive-pair list gives the same
// steps, bit for bit, as walking both trees every step; and group bodies kept by refresh between
// clips rest where and as still as with a clip every step.
#include "tests/bullet_ext/shape/group_scene.h"
#include "tests/bullet_ext/shape/scoped_contact_settings.h"

#include <shatter/bullet_ext/AttachedWorld.h>
#include <shatter/bullet_ext/OrderedContacts.h>
#include <shatter/bullet_ext/shape/FragmentPairAlgorithm.h>
#include <shatter/bullet_ext/shape/GroupCollisionAlgorithms.h>
#include <shatter/bullet_ext/shape/HullLanes.h>
#include <shatter/bullet_ext/shape/HullPairContacts.h>

#include <BulletCollision/CollisionShapes/btConvexPolyhedron.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <memory>
#include <random>
#include <string>
#include <vector>

namespace shatter {
namespace {

using test::GroupWorld;

btTransform pose(double angle, double x, double y, double z) {
    return btTransform(btQuaternion(btVector3(1, 2, 3).normalized(), btScalar(angle)), btVector3(btScalar(x), btScalar(y), btScalar(z)));
}

// Group pairs that walk both trees whole every step, and ones that keep a list (the default
// slack) made by the pruned walk (relistDepth).
struct WalkOrList {
    HullPairContacts walk, list;
    WalkOrList() {
        walk.pairListSlack = 0;
        walk.pruneRelist = false;
        list.pairListSlack = 0.005;
    }
};

// Each body's centre of mass, linear and angular velocity, interleaved per axis (9 a body).
std::vector<btScalar> finalStates(const std::vector<btRigidBody*>& bodies) {
    std::vector<btScalar> state;
    for (const btRigidBody* b : bodies)
        for (int i = 0; i < 3; ++i) {
            state.push_back(b->getCenterOfMassPosition()[i]);
            state.push_back(b->getLinearVelocity()[i]);
            state.push_back(b->getAngularVelocity()[i]);
        }
    return state;
}

// The contacts of the world a run steps: the plain test world's (Bullet's order, every leaf
// pair keeps its manifold), or the Plugin's default, taken in their own order with empty leaf
// manifolds freed (OrderedContacts.h, HullPairContacts::keepEmptyLeafManifolds off), where a
// hull pair's manifold is made and freed again as it finds points or none.
enum class Contacts { plain, ordered };

// A test world whose solver takes the contacts in their own order if `ordered`, as the Plugin
// sets it up (as ordered_contacts_test.cpp's OrderedWorld).
struct ContactsWorld {
    GroupWorld w;
    std::unique_ptr<OrderedContactSolver> solver;
    std::unique_ptr<AttachedWorld> attached;
    explicit ContactsWorld(Contacts contacts) {
        if (contacts == Contacts::plain) return;
        solver = std::make_unique<OrderedContactSolver>(*w.world().getConstraintSolver());
        attached = std::make_unique<AttachedWorld>(w.dispatcher());
        w.world().setConstraintSolver(solver.get());
        attached->setContactsOrdered(true);
    }
    ~ContactsWorld() {
        if (solver) w.world().setConstraintSolver(&solver->inner());
    }
};

// A run's end: every body's final state (finalStates), and how many manifolds the dispatcher
// holds, all and those with points.
struct RunEnd {
    std::vector<btScalar> state;
    int manifolds = 0;
    int manifoldsWithPoints = 0;
};
RunEnd runEnd(GroupWorld& w, const std::vector<btRigidBody*>& bodies) {
    RunEnd end{finalStates(bodies)};
    end.manifolds = w.dispatcher().getNumManifolds();
    for (int m = 0; m < end.manifolds; ++m)
        end.manifoldsWithPoints += w.dispatcher().getManifoldByIndexInternal(m)->getNumContacts() > 0;
    return end;
}

// Two runs' ends are the same, bit for bit.
void expectSameEnds(const RunEnd& a, const RunEnd& b, const char* what) {
    ASSERT_EQ(a.state.size(), b.state.size()) << what;
    for (size_t i = 0; i < a.state.size(); ++i) EXPECT_EQ(a.state[i], b.state[i]) << "component " << i << ", " << what;
    EXPECT_EQ(a.manifolds, b.manifolds) << what;
    EXPECT_EQ(a.manifoldsWithPoints, b.manifoldsWithPoints) << what;
}

// Six L shapes dropped turned onto a slab floor (a static group), piling up: group-group pairs
// of every kind (floor-L, L-L, resting and sliding) for 1.5 s.
RunEnd pileOfLs(const HullPairContacts& settings, Contacts contacts = Contacts::plain) {
    const test::ScopedContactSettings scope(settings);
    ContactsWorld o(contacts);
    GroupWorld& w = o.w;
    w.addStaticGroup(test::slabFloor(8, 8, 0.5));
    std::vector<btRigidBody*> bodies;
    for (int k = 0; k < 6; ++k)
        bodies.push_back(w.addGroup(test::lShape(), pose(0.7 * k, 0.05 * (k % 2), 0.15 + 0.18 * k, 0.04 * (k % 3)), 0.004));
    w.step(360);
    return runEnd(w, bodies);
}

TEST(GroupPairList, GivesTheSameStepsAsWalkingBothTreesEveryStep) {
    const WalkOrList s;
    const auto a = pileOfLs(s.walk).state, b = pileOfLs(s.list).state;
    ASSERT_EQ(a.size(), b.size());
    for (size_t k = 0; k < a.size(); k += 9) EXPECT_GT(a[k + 3], 0.0f) << "every L lies on the floor or another L";
    for (size_t i = 0; i < a.size(); ++i) EXPECT_EQ(a[i], b[i]) << "component " << i;
}

// Leaf pairs proven apart (HullPairContacts::skipProvenApart) skip their test only while it
// would find the same face and add nothing, and new pairs apart by a face plane skip the full
// separating-axis test only when it would find them apart: the pile of Ls (landing, sliding,
// resting, with pairs coming into contact at every stage) takes the same steps, bit for bit,
// as when every pair is tested every step, with the same manifolds left, and the skip does
// happen. In both worlds: the plain one, and the Plugin's default, where a skipped new pair
// must make and free its manifold as its full test would, and proofs stand on pairs without a
// manifold. (It fails when the proof's budget is overstated, or when new pairs 3 mm into each
// other count as apart.)
TEST(GroupPairProvenApart, GivesTheSameStepsAsTestingEveryPairEveryStep) {
    HullPairContacts tested, skipped;
    tested.skipProvenApart = false;
    skipped.skipProvenApart = true;
    for (const Contacts contacts : {Contacts::plain, Contacts::ordered}) {
        const char* what = contacts == Contacts::plain ? "plain world" : "own order, empty manifolds freed";
        const std::uint64_t before = provenApartSkips();
        const RunEnd a = pileOfLs(tested, contacts);
        EXPECT_EQ(provenApartSkips(), before) << "nothing skipped when the skip is off, " << what;
        const RunEnd b = pileOfLs(skipped, contacts);
        EXPECT_GT(provenApartSkips(), before + 1000) << "pairs at rest apart skip their tests, " << what;
        for (size_t k = 0; k < a.state.size(); k += 9)
            EXPECT_GT(a.state[k + 3], 0.0f) << "every L lies on the floor or another L, " << what;
        EXPECT_GT(a.manifoldsWithPoints, 0) << what;
        if (contacts == Contacts::ordered) EXPECT_EQ(a.manifolds, a.manifoldsWithPoints) << "empty manifolds freed";
        else EXPECT_GT(a.manifolds, a.manifoldsWithPoints) << "empty manifolds kept, " << what;
        expectSameEnds(a, b, what);
    }
}

// Small L shapes spun fast on a large slab floor: their lists are kept by the smaller body's
// turn (GroupGroupAlgorithm::listStillHolds) and must still hold every pair a walk of both trees
// would find. Bullet makes the body added first body0, so `floorLast` puts the floor, and its
// radius, on body1's side.
RunEnd spinningLsOnALargeFloor(const HullPairContacts& settings, bool floorLast, Contacts contacts = Contacts::plain) {
    const test::ScopedContactSettings scope(settings);
    ContactsWorld o(contacts);
    GroupWorld& w = o.w;
    if (!floorLast) w.addStaticGroup(test::slabFloor(16, 16, 0.5));
    std::vector<btRigidBody*> bodies;
    for (int k = 0; k < 4; ++k) {
        bodies.push_back(w.addGroup(test::lShape(), pose(0.9 * k, 1.5 * (k - 1.5), 0.45, 0.3 * k), 0.004));
        bodies.back()->setAngularVelocity(btVector3(btScalar(2 * k), 25, btScalar(-3 * k)));
    }
    if (floorLast) w.addStaticGroup(test::slabFloor(16, 16, 0.5));
    w.step(240);
    return runEnd(w, bodies);
}

TEST(GroupPairList, ASmallBodySpinningOnALargeOneGivesTheSameStepsAsWalkingBothTrees) {
    const WalkOrList s;
    for (const bool floorLast : {false, true}) {
        const auto a = spinningLsOnALargeFloor(s.walk, floorLast).state,
                   b = spinningLsOnALargeFloor(s.list, floorLast).state;
        ASSERT_EQ(a.size(), b.size());
        for (size_t k = 0; k < a.size(); k += 9) {
            EXPECT_GT(a[k + 3], 0.0f) << "every L lies on the floor";
            EXPECT_LT(a[k + 3], 0.3f) << "every L lies on the floor";
        }
        for (size_t i = 0; i < a.size(); ++i) EXPECT_EQ(a[i], b[i]) << "component " << i << ", floor last " << floorLast;
    }
}

// Fast-turning bodies move their leaves far between steps: proofs must run out in time. In
// both worlds, as above.
TEST(GroupPairProvenApart, SpinningBodiesGiveTheSameStepsAsTestingEveryPairEveryStep) {
    HullPairContacts tested, skipped;
    tested.skipProvenApart = false;
    for (const Contacts contacts : {Contacts::plain, Contacts::ordered})
        for (const bool floorLast : {false, true}) {
            const std::string what = std::string(contacts == Contacts::plain ? "plain world" : "own order") +
                                     ", floor last " + (floorLast ? "yes" : "no");
            const std::uint64_t before = provenApartSkips();
            const RunEnd a = spinningLsOnALargeFloor(tested, floorLast, contacts);
            const RunEnd b = spinningLsOnALargeFloor(skipped, floorLast, contacts);
            EXPECT_GT(provenApartSkips(), before) << what;
            expectSameEnds(a, b, what.c_str());
        }
}

// test::stackOfBoxes with these contact settings.
test::BoxStack stackOfBoxes(const HullPairContacts& settings) {
    const test::ScopedContactSettings scope(settings);
    GroupWorld w;
    return test::stackOfBoxes(w);
}

TEST(GroupLeafReclip, AStackRestsWhereAndAsStillAsWithAClipEveryStep) {
    HullPairContacts everyStep, kept;
    everyStep.reclipAfter = 0;
    kept.reclipAfter = 0.25;
    const test::BoxStack a = stackOfBoxes(everyStep), b = stackOfBoxes(kept);
    for (size_t k = 0; k < a.heights.size(); ++k) EXPECT_NEAR(b.heights[k], a.heights[k], 2e-4) << "box " << k;
    EXPECT_LT(a.fastest, 1e-3);
    EXPECT_LT(b.fastest, 1e-3) << "kept manifolds must not make the stack jitter";
}

TEST(SeparatingFace, TheFaceTriedFirstChangesOnlyTheCostNeverTheAnswer) {
    // Random poses of two boxes: with any hint, a face is found exactly when one exists, and
    // the face returned does separate them.
    auto hull = [](double h) {
        auto s = std::make_unique<btConvexHullShape>();
        for (int i = 0; i < 8; ++i)
            s->addPoint(btVector3(btScalar(i & 1 ? h : -h), btScalar(i & 2 ? h : -h), btScalar(i & 4 ? h : -h)), false);
        s->setMargin(0);
        s->recalcLocalAabb();
        s->initializePolyhedralFeatures();
        return s;
    };
    const auto a = hull(0.1), b = hull(0.07);
    btCollisionObject oa, ob;
    oa.setCollisionShape(a.get());
    ob.setCollisionShape(b.get());
    const int faces = a->getConvexPolyhedron()->m_faces.size() + b->getConvexPolyhedron()->m_faces.size();
    std::srand(5);
    auto unit = [] { return double(std::rand()) / RAND_MAX; };
    int apart = 0, near = 0;
    for (int trial = 0; trial < 1000; ++trial) {
        ob.setWorldTransform(pose(6 * unit(), 0.4 * unit() - 0.2, 0.4 * unit() - 0.2, 0.4 * unit() - 0.2));
        const btCollisionObjectWrapper wa(nullptr, a.get(), &oa, oa.getWorldTransform(), -1, -1);
        const btCollisionObjectWrapper wb(nullptr, b.get(), &ob, ob.getWorldTransform(), -1, -1);
        const int found = separatingFace(&wa, &wb, 0.001f);
        (found >= 0 ? apart : near) += 1;
        const RelativePose relative(oa.getWorldTransform(), ob.getWorldTransform());
        for (int hint = -1; hint < faces + 2; ++hint) {
            const int f = separatingFace(&wa, &wb, 0.001f, hint);
            EXPECT_EQ(f >= 0, found >= 0) << "trial " << trial << " hint " << hint;
            EXPECT_EQ(separatingFace(*a->getConvexPolyhedron(), *b->getConvexPolyhedron(), relative, 0.001f, hint), f)
                << "the pose made once gives the same face";
            if (f >= 0 && f != found) {
                EXPECT_EQ(separatingFace(&wa, &wb, 0.001f, f), f) << "a separating face tried first is kept";
            }
        }
    }
    EXPECT_GT(apart, 100);
    EXPECT_GT(near, 100);
}

// The face separatingFace documents, found vertex by vertex: a's faces with b's vertices mapped
// by bToA, then b's with a's mapped by its inverse; `hint` first on its side.
int faceVertexByVertex(const btConvexPolyhedron& a, const btConvexPolyhedron& b, const btTransform& bToA, btScalar gap,
                       int hint) {
    const auto of = [gap](const btConvexPolyhedron& planes, const btConvexPolyhedron& other, const btTransform& t, int h) {
        const auto separates = [&](int f) {
            const btScalar* p = planes.m_faces[f].m_plane;
            btScalar nearest = BT_LARGE_FLOAT;
            for (int v = 0; v < other.m_vertices.size(); ++v)
                nearest = btMin(nearest, btVector3(p[0], p[1], p[2]).dot(t * other.m_vertices[v]) + p[3]);
            return nearest > gap;
        };
        if (h >= 0 && separates(h)) return h;
        for (int f = 0; f < planes.m_faces.size(); ++f)
            if (f != h && separates(f)) return f;
        return -1;
    };
    const int facesA = a.m_faces.size();
    const auto ofB = [&](int h) {
        const int g = of(b, a, bToA.inverse(), h);
        return g < 0 ? -1 : facesA + g;
    };
    if (hint >= facesA) {
        const int g = ofB(hint - facesA);
        return g >= 0 ? g : of(a, b, bToA, -1);
    }
    const int f = of(a, b, bToA, hint);
    return f >= 0 ? f : ofB(-1);
}

// b in a random pose against a, with gaps at the exact distance of a's first face's nearest
// vertex and a float either side of it, and every hint: separatingFace gives the face found
// vertex by vertex. Counts the cases apart and near.
void expectFacesFoundVertexByVertex(const btConvexPolyhedron& a, const btConvexPolyhedron& b, std::mt19937& rng,
                                    int trial, int& apart, int& near) {
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    const btTransform ta = pose(3 * u(rng), 0.1 * u(rng), 0.1 * u(rng), 0.1 * u(rng));
    const btTransform tb = pose(3 * u(rng), 0.1 * u(rng) + 0.08, 0.1 * u(rng), 0.1 * u(rng));
    const RelativePose relative(ta, tb);
    // The nearest vertex of b to a's first face: a gap exactly there separates nothing by it.
    const btScalar* p = a.m_faces[0].m_plane;
    btScalar nearest = BT_LARGE_FLOAT;
    for (int v = 0; v < b.m_vertices.size(); ++v)
        nearest = btMin(nearest, btVector3(p[0], p[1], p[2]).dot(relative.bToA * b.m_vertices[v]) + p[3]);
    for (const btScalar gap : {btScalar(0), nearest, std::nextafter(nearest, -BT_LARGE_FLOAT),
                               std::nextafter(nearest, BT_LARGE_FLOAT)})
        for (int hint = -1; hint < a.m_faces.size() + b.m_faces.size(); ++hint) {
            const int expected = faceVertexByVertex(a, b, relative.bToA, gap, hint);
            EXPECT_EQ(separatingFace(a, b, relative, gap, hint), expected) << "trial " << trial << " hint " << hint;
            (expected >= 0 ? apart : near) += 1;
        }
}

std::unique_ptr<btConvexHullShape> marginlessHull(const std::vector<btVector3>& points) {
    auto s = std::make_unique<btConvexHullShape>();
    for (const btVector3& p : points) s->addPoint(p, false);
    s->setMargin(0);
    s->recalcLocalAabb();
    s->initializePolyhedralFeatures();
    return s;
}

TEST(SeparatingFace, SmallHullsInLanesGiveTheFaceFoundVertexByVertex) {
    // Tets (their vertices in lanes) and a 12-vertex hull (vertex by vertex), in random poses.
    std::mt19937 rng(9);
    const auto tet = marginlessHull({{0, 0, 0}, {0.1f, 0, 0}, {0, 0.1f, 0}, {0, 0, 0.1f}});
    std::vector<btVector3> ring;
    for (int k = 0; k < 6; ++k)
        for (const float z : {-0.05f, 0.05f})
            ring.emplace_back(0.08f * std::cos(1.047f * k), 0.08f * std::sin(1.047f * k), z);
    const auto prism = marginlessHull(ring);
    int apart = 0, near = 0;
    for (int trial = 0; trial < 600; ++trial)
        expectFacesFoundVertexByVertex(*tet->getConvexPolyhedron(), *(trial % 3 == 0 ? prism : tet)->getConvexPolyhedron(),
                                       rng, trial, apart, near);
    EXPECT_GT(apart, 1000);
    EXPECT_GT(near, 1000);
}

TEST(SeparatingFace, HullsThatKeepTheirLanesGiveTheFaceFoundVertexByVertex) {
    // A group's leaf hulls keep their vertices and planes in lanes (HullLanes.h): a tet and a
    // skewed 8-vertex box (two vertex blocks, six faces), each against each, and against a
    // hull that keeps none.
    std::mt19937 rng(10);
    const auto tet = marginlessHull({{0, 0, 0}, {0.1f, 0, 0}, {0, 0.1f, 0}, {0, 0, 0.1f}});
    std::vector<btVector3> corners;
    for (int k = 0; k < 8; ++k)
        corners.emplace_back(k & 1 ? 0.06f : -0.05f, k & 2 ? 0.04f + 0.01f * float(k & 1) : -0.04f, k & 4 ? 0.05f : -0.06f);
    const auto box = marginlessHull(corners);
    const auto keeping = [](const btConvexHullShape& hull) {
        auto laned = std::make_unique<LanedPolyhedron>();
        static_cast<btConvexPolyhedron&>(*laned) = *hull.getConvexPolyhedron();
        laned->refreshLanes();
        return laned;
    };
    const auto lanedTet = keeping(*tet), lanedBox = keeping(*box);
    ASSERT_EQ(lanedBox->lanes().vertexBlocks, 2);
    const btConvexPolyhedron* hulls[] = {lanedTet.get(), lanedBox.get(), tet->getConvexPolyhedron()};
    int apart = 0, near = 0;
    for (int trial = 0; trial < 600; ++trial)
        expectFacesFoundVertexByVertex(*hulls[trial % 2], *hulls[(trial / 2) % 3], rng, trial, apart, near);
    EXPECT_GT(apart, 1000);
    EXPECT_GT(near, 1000);
}

TEST(LanedPolyhedron, OwnFrontIsHowFarItsVerticesStandInFrontOfItsOwnPlanes) {
    // A new pair apart by a face by more than this (and rounding) skips the full test
    // (GroupCollisionAlgorithms.cpp, newPairApart): it must see a vertex off its face's plane.
    const auto tet = marginlessHull({{0, 0, 0}, {0.1f, 0, 0}, {0, 0.1f, 0}, {0, 0, 0.1f}});
    LanedPolyhedron laned;
    static_cast<btConvexPolyhedron&>(laned) = *tet->getConvexPolyhedron();
    laned.refreshLanes();
    EXPECT_GE(laned.ownFront(), 0.0);
    EXPECT_LT(laned.ownFront(), 1e-7) << "a tet's vertices lie on its planes, to rounding";
    laned.m_faces[0].m_plane[3] += 0.01f; // the plane moved back: its vertices 1 cm in front
    laned.refreshLanes();
    EXPECT_NEAR(laned.ownFront(), 0.01, 1e-6);
}

} // namespace
} // namespace shatter
