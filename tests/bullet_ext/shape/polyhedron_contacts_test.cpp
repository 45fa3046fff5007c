// Contacts of two small polyhedra (PolyhedronContacts.h): the same axis and points as Bullet's
// separating-axis test and clipping, up to rounding; the box as a polyhedron; the one point of
// a hull over a box, as GJK's but exact; and a group's
// primitives on a btBoxShape (HullPairContacts::boxLeavesClipped) resting still on its surface.
#include "tests/bullet_ext/shape/group_scene.h"
#include "tests/bullet_ext/shape/scoped_contact_settings.h"
#include "tests/support/SameBits.h"

#include <shatter/bullet_ext/shape/HullLanes.h>
#include <shatter/bullet_ext/shape/HullPairContacts.h>
#include <shatter/bullet_ext/shape/PolyhedronContacts.h>

#include <BulletCollision/NarrowPhaseCollision/btPolyhedralContactClipping.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <vector>

namespace shatter {
namespace {

struct Point {
    btVector3 normal, point;
    btScalar depth;
};

struct Points : btDiscreteCollisionDetectorInterface::Result {
    std::vector<Point> points;
    void setShapeIdentifiersA(int, int) override {}
    void setShapeIdentifiersB(int, int) override {}
    void addContactPoint(const btVector3& n, const btVector3& p, btScalar depth) override { points.push_back({n, p, depth}); }
};

// A hull with polyhedral features over `points`, as a fragment's or a group's leaf has.
std::unique_ptr<btConvexHullShape> hullOf(const std::vector<btVector3>& points) {
    auto hull = std::make_unique<btConvexHullShape>();
    for (const btVector3& p : points) hull->addPoint(p, false);
    hull->recalcLocalAabb();
    hull->initializePolyhedralFeatures();
    return hull;
}

btTransform randomPose(std::mt19937& rng, double spread) {
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    const btQuaternion turn(btVector3(btScalar(u(rng)), btScalar(u(rng)), btScalar(u(rng))).normalized(),
                            btScalar(3.0 * u(rng)));
    return btTransform(turn, btVector3(btScalar(spread * u(rng)), btScalar(spread * u(rng)), btScalar(spread * u(rng))));
}

std::vector<btVector3> randomTet(std::mt19937& rng) {
    std::uniform_real_distribution<double> u(-0.05, 0.05);
    std::vector<btVector3> p;
    for (int k = 0; k < 4; ++k) p.emplace_back(btScalar(u(rng)), btScalar(u(rng)), btScalar(u(rng)));
    return p;
}

// x, y and z with their bits (== takes -0 for +0, and a zero's sign is what the lanes must keep).
bool sameBits(const btVector3& a, const btVector3& b) { return std::memcmp(a.m_floats, b.m_floats, 3 * sizeof(btScalar)) == 0; }
using shatter::test::sameBits;

// The separating-axis test against Bullet's on one pair: the verdict, the axis and, for an
// edge pair, its points, bit for bit. Counts the case; true when the hulls overlap.
struct AxisTally {
    int overlapping = 0, apart = 0, edgeAxes = 0;
};
bool expectBulletsAxis(const btConvexPolyhedron& a, const btTransform& ta, const btConvexPolyhedron& b,
                       const btTransform& tb, int trial, AxisTally& tally) {
    Points bullet, ours;
    btVector3 bulletNormal, ourNormal;
    const bool bulletOverlap = btPolyhedralContactClipping::findSeparatingAxis(a, b, ta, tb, bulletNormal, bullet);
    EXPECT_EQ(leastOverlapAxis(a, ta, b, tb, ourNormal, ours), bulletOverlap) << "trial " << trial;
    if (!bulletOverlap) {
        ++tally.apart;
        return false;
    }
    ++tally.overlapping;
    EXPECT_TRUE(sameBits(ourNormal, bulletNormal)) << "trial " << trial;
    EXPECT_EQ(ours.points.size(), bullet.points.size()) << "trial " << trial;
    for (size_t k = 0; k < std::min(ours.points.size(), bullet.points.size()); ++k) {
        EXPECT_TRUE(sameBits(ours.points[k].point, bullet.points[k].point)) << "trial " << trial;
        EXPECT_TRUE(sameBits(ours.points[k].depth, bullet.points[k].depth)) << "trial " << trial;
    }
    tally.edgeAxes += int(bullet.points.size());
    return true;
}

// A copy of h that keeps its lanes, as a group's leaf hull does (HullLanes.h).
std::unique_ptr<LanedPolyhedron> laned(const btConvexPolyhedron& h) {
    auto copy = std::make_unique<LanedPolyhedron>();
    static_cast<btConvexPolyhedron&>(*copy) = h;
    copy->refreshLanes();
    return copy;
}

// The same with a many-sided hull and a small one, the big one first on even trials, so that
// either argument of the test is the big hull.
void expectBulletsAxisEitherWay(const btConvexPolyhedron& big, const btTransform& tBig, const btConvexPolyhedron& small,
                                const btTransform& tSmall, int trial, AxisTally& tally) {
    if (trial % 2 == 0) expectBulletsAxis(big, tBig, small, tSmall, trial, tally);
    else expectBulletsAxis(small, tSmall, big, tBig, trial, tally);
}

// Tets against tets and against boxes at random poses around each other, some apart, most
// overlapping: the verdict, the axis and every point are Bullet's, bit for bit.
TEST(PolyhedronContacts, GiveBulletsAxisAndPointsBitForBit) {
    std::mt19937 rng(7);
    const btConvexPolyhedron box = boxPolyhedron(btVector3(0.06f, 0.02f, 0.04f));
    AxisTally tally;
    for (int trial = 0; trial < 600; ++trial) {
        const auto tetA = hullOf(randomTet(rng));
        const auto tetB = hullOf(randomTet(rng));
        const btConvexPolyhedron& a = *tetA->getConvexPolyhedron();
        const btConvexPolyhedron& b = trial % 3 == 2 ? box : *tetB->getConvexPolyhedron();
        const btTransform ta = randomPose(rng, 0.5);
        const btTransform tb = ta * randomPose(rng, 0.06);

        if (!expectBulletsAxis(a, ta, b, tb, trial, tally)) continue;

        // The whole contact, clipping included, into collectors of both.
        Points bulletAll, ourAll;
        btVertexArray v1, v2;
        btVector3 n;
        btPolyhedralContactClipping::findSeparatingAxis(a, b, ta, tb, n, bulletAll);
        btPolyhedralContactClipping::clipHullAgainstHull(n, a, b, ta, tb, btScalar(-1e30), btScalar(0.02), v1, v2, bulletAll);
        polyhedronContacts(a, ta, b, tb, btScalar(0.02), ourAll);
        ASSERT_EQ(ourAll.points.size(), bulletAll.points.size()) << "trial " << trial;
        for (size_t k = 0; k < ourAll.points.size(); ++k) {
            EXPECT_EQ(ourAll.points[k].point, bulletAll.points[k].point) << "trial " << trial;
            EXPECT_EQ(ourAll.points[k].depth, bulletAll.points[k].depth) << "trial " << trial;
            EXPECT_EQ(ourAll.points[k].normal, bulletAll.points[k].normal) << "trial " << trial;
        }
    }
    // The trials cover every case.
    EXPECT_GT(tally.overlapping, 100);
    EXPECT_GT(tally.apart, 100);
    EXPECT_GT(tally.edgeAxes, 10);
}

// A many-sided hull (a fragment of a user's mesh) against tets and boxes, as either argument,
// from deep overlap to apart: the larger hull is read vertex by vertex and most axes end
// early (PolyhedronContacts.cpp); the verdict, axis and points are still Bullet's.
TEST(PolyhedronContacts, GiveBulletsAxisAndPointsForAManySidedHullEitherWay) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    const btConvexPolyhedron box = boxPolyhedron(btVector3(0.03f, 0.01f, 0.02f));
    AxisTally tally;
    for (int trial = 0; trial < 300; ++trial) {
        std::vector<btVector3> blob;
        for (int k = 0; k < 60; ++k)
            blob.push_back(btVector3(btScalar(u(rng)), btScalar(u(rng)), btScalar(u(rng))).normalized() *
                           btScalar(0.1 + 0.02 * u(rng)));
        const auto many = hullOf(blob);
        const auto tet = hullOf(randomTet(rng));
        const btConvexPolyhedron& big = *many->getConvexPolyhedron();
        const btConvexPolyhedron& small = trial % 4 == 3 ? box : *tet->getConvexPolyhedron();
        const btTransform tBig = randomPose(rng, 0.5);
        const btTransform tSmall = tBig * randomPose(rng, 0.14);
        expectBulletsAxisEitherWay(big, tBig, small, tSmall, trial, tally);
    }
    EXPECT_GT(tally.overlapping, 50);
    EXPECT_GT(tally.apart, 50);
    EXPECT_GT(tally.edgeAxes, 5);
}

// Pieces of a broken mesh resting on each other: a many-sided hull (half a blob, cut flat)
// against tets and prisms whose face lies in its cut, either argument, a hair into it, on it
// or off it, turned a little or not at all. Many edge pairs then give the cut's normal up to
// rounding, as its face does: ties the least-overlap rule settles by order. The edge axes'
// bounds (a sample of vertices, four axes at a time) must leave Bullet's choice unchanged.
TEST(PolyhedronContacts, GiveBulletsAxisAndPointsForPiecesTouchingAlongACut) {
    std::mt19937 rng(13);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    AxisTally tally;
    for (int trial = 0; trial < 300; ++trial) {
        std::vector<btVector3> half;
        for (int k = 0; k < 50; ++k) {
            btVector3 p = btVector3(btScalar(u(rng)), btScalar(u(rng)), btScalar(u(rng))).normalized() * btScalar(0.1);
            p.setZ(btFabs(p.z()));
            half.push_back(p);
        }
        for (int k = 0; k < 12; ++k) // the cut's rim
            half.push_back(btVector3(btScalar(0.1 * std::cos(k * 0.5236)), btScalar(0.1 * std::sin(k * 0.5236)), 0));
        std::vector<btVector3> piece; // a face in the cut (z = 0), the rest below it
        const int corners = 3 + trial % 2;
        const btVector3 at(btScalar(0.05 * u(rng)), btScalar(0.05 * u(rng)), 0);
        for (int k = 0; k < corners; ++k)
            piece.push_back(at + btVector3(btScalar(0.02 * std::cos(k * 6.2832 / corners + u(rng))),
                                           btScalar(0.02 * std::sin(k * 6.2832 / corners + u(rng))), 0));
        for (int k = 0; k < corners - 2; ++k)
            piece.push_back(at + btVector3(btScalar(0.01 * u(rng)), btScalar(0.01 * u(rng)), btScalar(-0.02)));
        const auto many = hullOf(half);
        const auto small = hullOf(piece);
        const btTransform tBig = randomPose(rng, 0.5);
        const btScalar offsets[] = {btScalar(-1e-4), btScalar(-1e-6), 0, btScalar(1e-6)};
        btTransform rel = btTransform::getIdentity();
        rel.setOrigin(btVector3(0, 0, offsets[trial % 4]));
        if (trial % 3 == 0) rel.setRotation(btQuaternion(btVector3(btScalar(u(rng)), btScalar(u(rng)), 0).normalized(), btScalar(1e-3)));
        const btTransform tSmall = tBig * rel;
        expectBulletsAxisEitherWay(*many->getConvexPolyhedron(), tBig, *small->getConvexPolyhedron(), tSmall, trial, tally);
    }
    EXPECT_GT(tally.overlapping, 100);
    EXPECT_GT(tally.apart, 100);
}

// Small hulls (up to 8 vertices: every axis tried four at a time) sharing a face, as a
// lattice's neighbouring tets do: a tet and one across its face, a prism on a tet's face,
// and boxes stacked face on face, the second a hair into, on or off the shared face, turned
// a little or not at all, the pair at a random pose or none. Many axes then tie (edge pairs in the face give its normal to the
// bit); the first least one wins, as Bullet's does.
TEST(PolyhedronContacts, GiveBulletsAxisAndPointsForSmallHullsSharingAFace) {
    std::mt19937 rng(29);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    AxisTally tally, lanedTally;
    for (int trial = 0; trial < 400; ++trial) {
        std::vector<btVector3> first, second;
        if (trial % 4 == 3) { // boxes: b on a's top face
            for (int k = 0; k < 8; ++k) {
                const btVector3 corner(k & 1 ? 0.03f : -0.03f, k & 2 ? 0.02f : -0.02f, k & 4 ? 0.01f : -0.01f);
                first.push_back(corner);
                second.push_back(corner + btVector3(btScalar(0.01 * u(rng)), btScalar(0.01 * u(rng)), 0.02f));
            }
        } else { // a tet; across its face (x, y, 0): another tet, or a prism (trial % 4 == 2)
            for (int k = 0; k < 3; ++k) {
                const btVector3 p(btScalar(0.03 * u(rng)), btScalar(0.03 * u(rng)), 0);
                first.push_back(p);
                second.push_back(p);
                if (trial % 4 == 2) second.push_back(p + btVector3(btScalar(0.005 * u(rng)), btScalar(0.005 * u(rng)), 0.02f));
            }
            first.push_back(btVector3(btScalar(0.01 * u(rng)), btScalar(0.01 * u(rng)), -0.03f));
            if (trial % 4 != 2) second.push_back(btVector3(btScalar(0.01 * u(rng)), btScalar(0.01 * u(rng)), 0.03f));
        }
        const auto a = hullOf(first);
        const auto b = hullOf(second);
        // Every eighth pair unturned, so that zero coordinates (and their signs) occur.
        const btTransform ta = trial % 8 == 0 ? btTransform::getIdentity() : randomPose(rng, 0.5);
        const btScalar offsets[] = {btScalar(-1e-4), btScalar(-1e-6), 0, btScalar(1e-6), btScalar(-1e-3)};
        btTransform rel = btTransform::getIdentity();
        rel.setOrigin(btVector3(0, 0, offsets[trial % 5]));
        if (trial % 3 == 0) rel.setRotation(btQuaternion(btVector3(btScalar(u(rng)), btScalar(u(rng)), 0).normalized(), btScalar(1e-3)));
        expectBulletsAxisEitherWay(*a->getConvexPolyhedron(), ta, *b->getConvexPolyhedron(), ta * rel, trial, tally);
        // Hulls that keep their lanes (a group's leaves), one or both.
        const auto lanedA = laned(*a->getConvexPolyhedron()), lanedB = laned(*b->getConvexPolyhedron());
        expectBulletsAxisEitherWay(*lanedA, ta, trial % 2 == 0 ? *lanedB : *b->getConvexPolyhedron(), ta * rel, trial,
                                   lanedTally);
    }
    EXPECT_EQ(lanedTally.overlapping, tally.overlapping);
    EXPECT_EQ(lanedTally.edgeAxes, tally.edgeAxes);
    EXPECT_GT(tally.overlapping, 100);
    EXPECT_GT(tally.apart, 20);
    EXPECT_GT(tally.edgeAxes, 5);
}

// Tets (and a tet against a box) sliding and turning past each other, from apart through
// overlap and apart again, with the separating axis carried from step to step as a pair's
// algorithm carries it: every step's verdict and points are those of the test without it, and
// the carried axis decides most separated steps on its own.
TEST(PolyhedronContacts, ACarriedSeparatingAxisChangesNoResult) {
    std::mt19937 rng(5);
    const btConvexPolyhedron box = boxPolyhedron(btVector3(0.06f, 0.02f, 0.04f));
    int apart = 0, overlapping = 0, byTheCarriedAxis = 0;
    for (int path = 0; path < 120; ++path) {
        const auto tetA = hullOf(randomTet(rng));
        const auto tetB = hullOf(randomTet(rng));
        const btConvexPolyhedron& a = *tetA->getConvexPolyhedron();
        const btConvexPolyhedron& b = path % 4 == 3 ? box : *tetB->getConvexPolyhedron();
        const btTransform ta = randomPose(rng, 0.5);
        // b passes a: from 12 cm off along a random line, through a's place, to 12 cm beyond,
        // turning a little each step.
        const btTransform start = randomPose(rng, 0.02);
        const btVector3 line = randomPose(rng, 1.0).getOrigin().normalized() * btScalar(0.12);
        const btQuaternion turn(randomPose(rng, 1.0).getOrigin().normalized(), btScalar(0.01));
        int axis = -1;
        for (int step = 0; step <= 80; ++step) {
            btTransform rel = start;
            rel.setOrigin(start.getOrigin() + line * btScalar(step / 40.0 - 1.0));
            rel.setRotation(start.getRotation() * btQuaternion(turn.getAxis(), turn.getAngle() * btScalar(step)));
            const btTransform tb = ta * rel;
            Points plain, carried;
            const int before = axis;
            const bool plainOverlap = polyhedronContacts(a, ta, b, tb, btScalar(0.02), plain);
            const bool carriedOverlap = polyhedronContacts(a, ta, b, tb, btScalar(0.02), carried, &axis);
            ASSERT_EQ(carriedOverlap, plainOverlap) << "path " << path << ", step " << step;
            ASSERT_EQ(carried.points.size(), plain.points.size()) << "path " << path << ", step " << step;
            for (size_t k = 0; k < plain.points.size(); ++k) {
                EXPECT_EQ(carried.points[k].point, plain.points[k].point);
                EXPECT_EQ(carried.points[k].depth, plain.points[k].depth);
                EXPECT_EQ(carried.points[k].normal, plain.points[k].normal);
            }
            if (plainOverlap) {
                ++overlapping;
                continue;
            }
            ++apart;
            EXPECT_GE(axis, 0); // the axis that separates them now is kept
            if (axis == before) ++byTheCarriedAxis;
        }
    }
    EXPECT_GT(overlapping, 500);
    EXPECT_GT(apart, 2000);
    EXPECT_GT(byTheCarriedAxis, apart / 2);
}

TEST(PolyhedronContacts, TheBoxHasOutwardCounterClockwiseFacesThroughItsCorners) {
    const btVector3 h(0.3f, 0.1f, 0.2f);
    const btConvexPolyhedron box = boxPolyhedron(h);
    ASSERT_EQ(box.m_vertices.size(), 8);
    ASSERT_EQ(box.m_faces.size(), 6);
    btVector3 normalSum(0, 0, 0);
    for (int f = 0; f < 6; ++f) {
        const btFace& face = box.m_faces[f];
        ASSERT_EQ(face.m_indices.size(), 4);
        const btVector3 n(face.m_plane[0], face.m_plane[1], face.m_plane[2]);
        normalSum += n;
        const btVector3* v[3] = {&box.m_vertices[face.m_indices[0]], &box.m_vertices[face.m_indices[1]],
                                 &box.m_vertices[face.m_indices[2]]};
        // Counter-clockwise seen from outside: the corners turn about the outward normal.
        EXPECT_GT((*v[1] - *v[0]).cross(*v[2] - *v[1]).normalized().dot(n), btScalar(0.9999)) << "face " << f;
        for (int k = 0; k < 4; ++k)
            EXPECT_NEAR(n.dot(box.m_vertices[face.m_indices[k]]) + face.m_plane[3], 0.0, 1e-7) << "face " << f;
        for (int k = 0; k < 8; ++k) EXPECT_LE(n.dot(box.m_vertices[k]) + face.m_plane[3], 1e-7) << "face " << f;
        // Through the box's surface: the face is h along its normal.
        EXPECT_NEAR(-face.m_plane[3], std::abs(n.dot(h)), 1e-7) << "face " << f;
    }
    EXPECT_LT(normalSum.length(), 1e-7);
}

// A small hull (a 2 × 1 × 2 cm brick, margin 4 mm, as a soft sheet's quad) tilted at random
// over the top of a box, from a little inside it to beyond its margin and threshold: the one
// contact of hullBoxContact is there exactly when GJK's would be (its distance, the lowest
// corner's height less the margin, within the threshold), with that distance, the face's
// normal and a point on the face under the brick. (Bullet's GJK itself is off by up to 3 mm
// and 0.5° here when a face of the brick lies nearly flat.)
TEST(HullBoxContact, GivesTheExactDistanceNormalAndPointForAHullOverABoxFace) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    const btScalar margin = 0.004f, threshold = 0.02f;
    std::vector<btVector3> corners;
    for (int k = 0; k < 8; ++k) corners.emplace_back(k & 1 ? 0.01f : -0.01f, k & 2 ? 0.005f : -0.005f, k & 4 ? 0.01f : -0.01f);
    const auto brick = hullOf(corners);
    const btVector3 half(0.5f, 0.3f, 0.5f);
    const btTransform boxPose(btQuaternion(btVector3(0, 1, 0), 0.4f), btVector3(0.2f, 0.1f, -0.3f));
    const btVector3 up = boxPose.getBasis() * btVector3(0, 1, 0);
    int contacts = 0, none = 0;
    for (int trial = 0; trial < 400; ++trial) {
        const btQuaternion tilt(btVector3(btScalar(u(rng)), btScalar(u(rng)), btScalar(u(rng))).normalized(), btScalar(0.3 * u(rng)));
        btTransform local(tilt, btVector3(btScalar(0.3 * u(rng)), 0, btScalar(0.3 * u(rng))));
        // The lowest corner at `gap` above the top face (negative: inside).
        btScalar lowest = BT_LARGE_FLOAT;
        for (const btVector3& c : corners) lowest = btMin(lowest, (local * c).y());
        const double gap = -0.003 + 0.03 * (0.5 + 0.5 * u(rng));
        local.getOrigin().setY(btScalar(half.y() + gap - lowest));
        const btTransform hullPose = boxPose * local;

        BoxContact c;
        const bool found = hullBoxContact(*brick->getConvexPolyhedron(), hullPose, margin, half, boxPose, threshold, c);
        ASSERT_EQ(found, gap - margin <= threshold) << "trial " << trial << " gap " << gap;
        if (!found) {
            ++none;
            continue;
        }
        ++contacts;
        EXPECT_NEAR(c.distance, gap - margin, 1e-6) << "trial " << trial;
        EXPECT_GT(c.normal.dot(up), btScalar(1 - 1e-6)) << "trial " << trial;
        const btVector3 onTop = boxPose.inverse() * c.onBox;
        EXPECT_NEAR(onTop.y(), half.y(), 1e-6) << "trial " << trial;
        EXPECT_LT(btVector3(onTop.x() - local.getOrigin().x(), 0, onTop.z() - local.getOrigin().z()).length(), 0.015)
            << "trial " << trial;
    }
    EXPECT_GT(contacts, 100);
    EXPECT_GT(none, 20);
}

// A group table dropped tilted onto a static box settles on the box's top face (no margin in
// between) and stays there: from 4 s to 6 s it moves less than 1 mm, no more than with GJK,
// and turns less than 0.001 rad, and a contact query finds it with the box's normal. Bullet's
// GJK path (the setting off, the default) rests a margin higher.
TEST(GroupOnBox, ATableSettlesOnTheBoxSurfaceAndStaysStill) {
    const auto run = [](bool clipped, double& restHeight, double& drift, double& turn) {
        HullPairContacts settings;
        settings.boxLeavesClipped = clipped;
        const test::ScopedContactSettings scope(settings);
        test::GroupWorld w;
        w.add(std::make_unique<btBoxShape>(btVector3(2, 0.1f, 2)), 0, btTransform(btQuaternion::getIdentity(), btVector3(0, -0.1f, 0)));
        const btTransform tilted(btQuaternion(btVector3(1, 0, 0.3f).normalized(), btScalar(0.15)), btVector3(0, 0.15f, 0));
        btRigidBody* table = w.addGroup(test::table(), tilted, 0.01);
        table->setActivationState(DISABLE_DEACTIVATION);
        w.step(960);
        const btTransform settled = table->getWorldTransform();
        w.step(480);
        const btTransform later = table->getWorldTransform();
        // A fresh query finds the resting contact too, with the box's normal, in both orders.
        struct Up : btCollisionWorld::ContactResultCallback {
            const btCollisionObject* table;
            btVector3 sum{0, 0, 0};
            btScalar addSingleResult(btManifoldPoint& cp, const btCollisionObjectWrapper* w0, int, int,
                                     const btCollisionObjectWrapper*, int, int) override {
                sum += w0->getCollisionObject() == table ? cp.m_normalWorldOnB : -cp.m_normalWorldOnB;
                return 0;
            }
        };
        btCollisionObject* box = w.world().getCollisionObjectArray()[0];
        for (int order = 0; order < 2; ++order) {
            Up up;
            up.table = table;
            if (order == 0) w.world().contactPairTest(table, box, up);
            else w.world().contactPairTest(box, table, up);
            EXPECT_GT(up.sum.normalized().y(), btScalar(0.999)) << "order " << order << (clipped ? " clipped" : " GJK");
        }
        drift = double((later.getOrigin() - settled.getOrigin()).length());
        turn = double(settled.getRotation().angleShortestPath(later.getRotation()));
        restHeight = double(later.getOrigin().y());
    };
    const double expected = test::restHeight(test::toBodyFrame(test::table()), 0.0);
    double height, drift, turn;
    run(true, height, drift, turn);
    EXPECT_NEAR(height, expected, 1e-3);
    EXPECT_LT(drift, 1e-3);
    EXPECT_LT(turn, 1e-3);
    double gjkHeight, gjkDrift, gjkTurn;
    run(false, gjkHeight, gjkDrift, gjkTurn);
    EXPECT_NEAR(gjkHeight, expected + 0.01, 2e-3); // the control: a margin higher
    EXPECT_LE(drift, gjkDrift); // and as still as with GJK (0.18 against 0.32 mm)
}

} // namespace
} // namespace shatter
