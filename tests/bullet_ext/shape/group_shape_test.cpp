// The group shape on its own: bounds, inertia, triangles, children, removal, bad input,
// registration.
#include <shatter/bullet_ext/shape/GroupCollisionAlgorithms.h>
#include <shatter/bullet_ext/shape/GroupShape.h>
#include <shatter/bullet_ext/shape/HullLanes.h>
#include <shatter/plugin/geometry/HoleFilling.h>
#include "tests/bullet_ext/shape/group_scene.h"
#include "tests/bullet_ext/shape/same_shape.h"

#include <BulletCollision/CollisionDispatch/btCollisionObjectWrapper.h>
#include <BulletCollision/CollisionDispatch/btCompoundCollisionAlgorithm.h>
#include <BulletCollision/CollisionShapes/btConvexPolyhedron.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <set>

using namespace shatter;
using namespace shatter::test;

namespace {

struct CountTriangles : btTriangleCallback {
    std::set<int> primitives;
    int triangles = 0;
    double area = 0;
    void processTriangle(btVector3* t, int partId, int) override {
        primitives.insert(partId);
        ++triangles;
        area += 0.5 * double((t[1] - t[0]).cross(t[2] - t[0]).length());
    }
};

// A leaf hull keeps its vertices and face planes (normals and offsets) in lanes (HullLanes.h),
// and they are the hull's as they are now, bit for bit.
void expectKeptLanes(const btConvexPolyhedron& poly) {
    const HullLanes* kept = keptLanes(poly);
    ASSERT_NE(kept, nullptr);
    HullLanes now;
    now.assign(poly);
    ASSERT_EQ(kept->vertexBlocks, now.vertexBlocks);
    ASSERT_EQ(kept->faceBlocks, now.faceBlocks);
    EXPECT_GT(kept->vertexBlocks, 0);
    EXPECT_GT(kept->faceBlocks, 0);
    EXPECT_EQ(std::memcmp(kept->vertices, now.vertices, sizeof(Vector4) * size_t(now.vertexBlocks)), 0);
    EXPECT_EQ(std::memcmp(kept->faceNormals, now.faceNormals, sizeof(Vector4) * size_t(now.faceBlocks)), 0);
    EXPECT_EQ(std::memcmp(kept->faceOffsets, now.faceOffsets, sizeof(Float4) * size_t(now.faceBlocks)), 0);
}

// `poly` turned by r and moved by t: vertices, and planes n·x + w = 0 as (r n)·x + w − (r n)·t = 0.
btConvexPolyhedron turned(btConvexPolyhedron poly, const btMatrix3x3& r, const btVector3& t) {
    for (int k = 0; k < poly.m_vertices.size(); ++k) poly.m_vertices[k] = r * poly.m_vertices[k] + t;
    for (int f = 0; f < poly.m_faces.size(); ++f) {
        btScalar* plane = poly.m_faces[f].m_plane;
        const btVector3 n = r * btVector3(plane[0], plane[1], plane[2]);
        plane[0] = n.x();
        plane[1] = n.y();
        plane[2] = n.z();
        plane[3] -= n.dot(t);
    }
    return poly;
}

} // namespace

TEST(GroupShape, BoundsIncludeTheMarginAndFollowTheTransform) {
    const GroupShape shape({boxPrimitive({0, 0, 0}, {1, 2, 3}), boxPrimitive({2, 0, 0}, {0.5, 0.5, 0.5})}, 0.05);
    btVector3 min, max;
    shape.getAabb(btTransform::getIdentity(), min, max);
    EXPECT_NEAR(min.x(), -1.05, 1e-6);
    EXPECT_NEAR(max.x(), 2.55, 1e-6);
    EXPECT_NEAR(min.z(), -3.05, 1e-6);
    // A quarter turn about z swaps the x and y extents.
    shape.getAabb(btTransform(btQuaternion(btVector3(0, 0, 1), SIMD_HALF_PI), btVector3(10, 0, 0)), min, max);
    EXPECT_NEAR(min.x(), 8.0 - 0.05, 1e-5);
    EXPECT_NEAR(max.x(), 12.0 + 0.05, 1e-5);
    EXPECT_NEAR(max.y(), 2.55, 1e-5);
    EXPECT_EQ(shape.getShapeType(), kGroupShapeType);
    EXPECT_TRUE(shape.isConcave());
    EXPECT_FLOAT_EQ(shape.getMargin(), 0.05f);
    EXPECT_FLOAT_EQ(shape.child(1).getMargin(), 0.05f);
}

TEST(GroupShape, InertiaIsThatOfTheSolidAboutTheBodyOrigin) {
    // One box 2 x 4 x 6 centred at the origin: I/m = (b² + c²)/12, ...
    const GroupShape one({boxPrimitive({0, 0, 0}, {1, 2, 3})}, 0.0);
    btVector3 inertia;
    one.calculateLocalInertia(2.0f, inertia);
    EXPECT_NEAR(inertia.x(), 2.0 * (16 + 36) / 12.0, 1e-5);
    EXPECT_NEAR(inertia.y(), 2.0 * (4 + 36) / 12.0, 1e-5);
    EXPECT_NEAR(inertia.z(), 2.0 * (4 + 16) / 12.0, 1e-5);
    // Two unit cubes at x = ±1: parallel axes add m·1² about y and z.
    const GroupShape two({boxPrimitive({-1, 0, 0}, {0.5, 0.5, 0.5}), boxPrimitive({1, 0, 0}, {0.5, 0.5, 0.5})}, 0.0);
    two.calculateLocalInertia(1.0f, inertia);
    EXPECT_NEAR(inertia.x(), 1.0 / 6.0, 1e-6);
    EXPECT_NEAR(inertia.y(), 1.0 / 6.0 + 1.0, 1e-6);
}

TEST(GroupShape, ProcessAllTrianglesGivesTheFacesOfOverlappingPrimitivesOnly) {
    const GroupShape shape({boxPrimitive({0, 0, 0}, {0.5, 0.5, 0.5}), boxPrimitive({5, 0, 0}, {0.5, 0.5, 0.5}),
                            prismPrimitive({10, 0, 0}, 1, 1, 1)},
                           0.01);
    CountTriangles all;
    shape.processAllTriangles(&all, btVector3(-100, -100, -100), btVector3(100, 100, 100));
    EXPECT_EQ(all.primitives, (std::set<int>{0, 1, 2}));
    EXPECT_EQ(all.triangles, 12 + 12 + 8); // quads fan into 2 triangles, the prism's ends are 1
    EXPECT_NEAR(all.area, 6 + 6 + (1 + 2 + std::sqrt(2.0)), 1e-5);
    CountTriangles near;
    shape.processAllTriangles(&near, btVector3(4.8, -0.1, -0.1), btVector3(4.9, 0.1, 0.1));
    EXPECT_EQ(near.primitives, (std::set<int>{1}));
}

TEST(GroupShape, ChildHullsCarryTheExactFaces) {
    const GroupShape shape({prismPrimitive({0, 0, 0}, 1, 2, 3)}, 0.02);
    const btConvexPolyhedron* poly = shape.child(0).getConvexPolyhedron();
    ASSERT_NE(poly, nullptr);
    EXPECT_EQ(poly->m_vertices.size(), 6);
    EXPECT_EQ(poly->m_faces.size(), 5);
    for (int f = 0; f < poly->m_faces.size(); ++f) {
        const btVector3 n(poly->m_faces[f].m_plane[0], poly->m_faces[f].m_plane[1], poly->m_faces[f].m_plane[2]);
        for (int i = 0; i < poly->m_faces[f].m_indices.size(); ++i) // every face vertex on its plane
            EXPECT_NEAR(n.dot(poly->m_vertices[poly->m_faces[f].m_indices[i]]) + poly->m_faces[f].m_plane[3], 0.0, 1e-5);
        for (int v = 0; v < poly->m_vertices.size(); ++v) // and the solid behind it (outward normals)
            EXPECT_LE(n.dot(poly->m_vertices[v]) + poly->m_faces[f].m_plane[3], 1e-5);
        // Bullet's separating-axis test skips axes using an inner sphere and box: both inside.
        const btScalar centreDistance = -(n.dot(poly->m_localCenter) + poly->m_faces[f].m_plane[3]);
        EXPECT_GE(centreDistance, poly->m_radius - 1e-6f);
        for (int c = 0; c < 8; ++c) {
            const btVector3 corner = poly->m_localCenter + btVector3(c & 1 ? 1 : -1, c & 2 ? 1 : -1, c & 4 ? 1 : -1) * poly->m_extents;
            EXPECT_LE(n.dot(corner) + poly->m_faces[f].m_plane[3], 1e-5);
        }
    }
    EXPECT_GT(poly->m_radius, 0.1f);
    EXPECT_EQ(poly->m_uniqueEdges.size(), 4); // x, y, the hypotenuse, z
    expectKeptLanes(*poly);
}

// Bullet's calls that remake or copy a hull's features leave a leaf hull's laned polyhedron in
// place (no dangling lanes: its soft steps still write them) with its exact faces and fresh lanes.
TEST(GroupShape, ChildHullsKeepTheirLanedFeaturesThroughBulletsFeatureCalls) {
    const std::vector<geometry::ConvexPolyhedron> rest{prismPrimitive({0, 0, 0}, 1, 2, 3)};
    GroupShape shape(rest, 0.02);
    auto& hull = const_cast<btConvexHullShape&>(shape.child(0));
    const btConvexPolyhedron* before = hull.getConvexPolyhedron();
    EXPECT_TRUE(hull.initializePolyhedralFeatures());
    EXPECT_EQ(hull.getConvexPolyhedron(), before);
    EXPECT_EQ(hull.getConvexPolyhedron()->m_faces.size(), 5); // the prism's own faces, not Bullet's hull
    expectKeptLanes(*hull.getConvexPolyhedron());

    const btConvexPolyhedron rested = *before;
    // Turned and moved by 1 m: the lanes follow the copy, offsets and normals too.
    btConvexPolyhedron copy = turned(rested, btMatrix3x3(btQuaternion(btVector3(1, 2, 3).normalized(), 0.7)), btVector3(1, 0, 0));
    hull.setPolyhedralFeatures(copy);
    EXPECT_EQ(hull.getConvexPolyhedron(), before);
    EXPECT_EQ(hull.getConvexPolyhedron()->m_vertices[0], copy.m_vertices[0]);
    EXPECT_EQ(hull.getConvexPolyhedron()->m_faces[0].m_plane[3], copy.m_faces[0].m_plane[3]);
    EXPECT_NE(copy.m_faces[0].m_plane[3], rested.m_faces[0].m_plane[3]); // the move changed the offsets
    expectKeptLanes(*hull.getConvexPolyhedron());

    Eigen::Isometry3d moved(Eigen::AngleAxisd(-1.1, Eigen::Vector3d(3, -1, 2).normalized())); // a soft step still moves the same polyhedron
    moved.translation() = Eigen::Vector3d(0, 2, 0);
    shape.setPrimitivePoses(rest, std::vector<Eigen::Isometry3d>{moved});
    EXPECT_EQ(shape.child(0).getConvexPolyhedron(), before);
    EXPECT_EQ(shape.child(0).getConvexPolyhedron()->m_vertices[0], toBullet(shape.primitives()[0].vertices()[0]));
    expectKeptLanes(*shape.child(0).getConvexPolyhedron());
}

// A soft step rewrites a child hull's vertices and faces by index: features with other counts
// (here one face fewer, or a vertex more) are refused, and the hull keeps its own.
TEST(GroupShape, ChildHullsRefuseFeaturesWithOtherCounts) {
    const std::vector<geometry::ConvexPolyhedron> rest{prismPrimitive({0, 0, 0}, 1, 2, 3)};
    GroupShape shape(rest, 0.02);
    auto& hull = const_cast<btConvexHullShape&>(shape.child(0));
    const btConvexPolyhedron* before = hull.getConvexPolyhedron();
    btConvexPolyhedron fewerFaces = *before, moreVertices = *before;
    fewerFaces.m_faces.pop_back();
    moreVertices.m_vertices.push_back(btVector3(0, 0, 0));
    EXPECT_THROW(hull.setPolyhedralFeatures(fewerFaces), InputError);
    EXPECT_THROW(hull.setPolyhedralFeatures(moreVertices), InputError);
    EXPECT_EQ(hull.getConvexPolyhedron(), before);
    EXPECT_EQ(before->m_faces.size(), 5);
    EXPECT_EQ(before->m_vertices.size(), 6);
    Eigen::Isometry3d moved = Eigen::Isometry3d::Identity(); // and the next soft step moves it as before
    moved.translation() = Eigen::Vector3d(0, 2, 0);
    shape.setPrimitivePoses(rest, std::vector<Eigen::Isometry3d>{moved});
    EXPECT_EQ(shape.child(0).getConvexPolyhedron(), before);
    EXPECT_EQ(before->m_vertices[0], toBullet(shape.primitives()[0].vertices()[0]));
    expectKeptLanes(*before);
}

TEST(GroupShape, ReplacedPrimitivesMoveTheirHullTreeAndBounds) {
    GroupShape shape({boxPrimitive({0, 0, 0}, {0.5, 0.5, 0.5}), boxPrimitive({2, 0, 0}, {0.5, 0.5, 0.5})}, 0.0);
    shape.replacePrimitives({1}, {boxPrimitive({2, 3, 0}, {0.5, 0.5, 0.5})});
    btVector3 lo, hi;
    shape.getAabb(btTransform::getIdentity(), lo, hi);
    EXPECT_FLOAT_EQ(float(hi.y()), 3.5f); // the bounds grew to the moved box
    std::set<int> found;
    shape.tree().query(geometry::Aabb{{1.9, 2.9, -0.1}, {2.1, 3.1, 0.1}}, [&](int i) { found.insert(i); });
    EXPECT_EQ(found, std::set<int>{1});
    EXPECT_FLOAT_EQ(float(shape.child(1).localGetSupportingVertex(btVector3(0, 1, 0)).y()), 3.5f);
    EXPECT_THROW(shape.replacePrimitives({2}, {boxPrimitive({0, 0, 0}, {1, 1, 1})}), InputError);
    EXPECT_THROW(shape.replacePrimitives({0, 1}, {boxPrimitive({0, 0, 0}, {1, 1, 1})}), InputError);
}

TEST(GroupShape, BadInputIsAnErrorAndScalingIsIgnored) {
    EXPECT_THROW(GroupShape({}, 0.04), InputError);
    EXPECT_THROW(GroupShape({boxPrimitive({0, 0, 0}, {1, 1, 1})}, -0.01), InputError);
    EXPECT_THROW(GroupShape({boxPrimitive({0, 0, 0}, {1, 1, 1})}, std::nan("")), InputError);
    GroupShape shape({boxPrimitive({0, 0, 0}, {1, 1, 1})}, 0.04);
    testing::internal::CaptureStderr();
    shape.setLocalScaling(btVector3(2, 2, 2));
    shape.setLocalScaling(btVector3(3, 3, 3));
    const std::string warning = testing::internal::GetCapturedStderr();
    EXPECT_NE(warning.find("setLocalScaling"), std::string::npos);
    EXPECT_EQ(warning.find("setLocalScaling"), warning.rfind("setLocalScaling")) << "reported once";
    EXPECT_EQ(shape.getLocalScaling(), btVector3(1, 1, 1));
    btVector3 min, max;
    shape.getAabb(btTransform::getIdentity(), min, max);
    EXPECT_NEAR(max.x(), 1.04, 1e-6);
}

TEST(GroupShape, SetMarginReachesTheChildren) {
    GroupShape shape({boxPrimitive({0, 0, 0}, {1, 1, 1}), boxPrimitive({3, 0, 0}, {1, 1, 1})}, 0.04);
    shape.setMargin(0.01f);
    EXPECT_FLOAT_EQ(shape.getMargin(), 0.01f);
    EXPECT_FLOAT_EQ(shape.child(0).getMargin(), 0.01f);
    btVector3 min, max;
    shape.getAabb(btTransform::getIdentity(), min, max);
    EXPECT_NEAR(max.x(), 4.01, 1e-6);
}

// A soft step moves a child hull only when it is first asked for, and the contact tree only
// when a group pair asks: whatever is read, after however many steps or before an edit, is
// where the last step put the primitives.
TEST(GroupShape, HullsAndContactTreeReadAfterSoftStepsAreWhereTheLastStepPutThem) {
    const std::vector<geometry::ConvexPolyhedron> rest{boxPrimitive({0, 0, 0}, {0.5, 0.5, 0.5}),
                                                       boxPrimitive({2, 0, 0}, {0.5, 0.5, 0.5})};
    GroupShape shape(rest, 0.01);
    const auto expectHullOn = [&](int i) {
        const btConvexHullShape& hull = shape.child(i);
        const auto& vertices = shape.primitives()[size_t(i)].vertices();
        ASSERT_EQ(hull.getNumPoints(), int(vertices.size()));
        for (size_t k = 0; k < vertices.size(); ++k) {
            EXPECT_EQ(hull.getUnscaledPoints()[k], toBullet(vertices[k]));
            EXPECT_EQ(hull.getConvexPolyhedron()->m_vertices[int(k)], toBullet(vertices[k]));
        }
        expectKeptLanes(*hull.getConvexPolyhedron()); // moved with the hull
        btVector3 lo, hi; // Bullet's box: the cached one (margin included) grown by the margin
        hull.getAabb(btTransform::getIdentity(), lo, hi);
        EXPECT_NEAR(lo.x(), shape.primitives()[size_t(i)].bounds().min.x() - 0.02, 1e-6);
        EXPECT_NEAR(hi.x(), shape.primitives()[size_t(i)].bounds().max.x() + 0.02, 1e-6);
    };
    Eigen::Isometry3d first = Eigen::Isometry3d::Identity(), second = Eigen::Isometry3d::Identity();
    first.translation() = Eigen::Vector3d(1, 0, 0);
    second = Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitZ());
    second.translation() = Eigen::Vector3d(3, 1, 0);
    shape.setPrimitivePoses(rest, std::vector<Eigen::Isometry3d>{first, first});
    shape.setPrimitivePoses(rest, std::vector<Eigen::Isometry3d>{second, first});
    expectHullOn(0); // turned and moved 3 m: read only after the second step
    expectHullOn(1);
    EXPECT_NEAR(shape.primitives()[0].bounds().max.x(), 3.0 + 0.5 * (std::cos(0.4) + std::sin(0.4)), 1e-12);
    std::set<int> found;
    shape.contactTree().query(geometry::Aabb{{2.9, 0.9, -0.1}, {3.1, 1.1, 0.1}}, [&](int i) { found.insert(i); });
    EXPECT_EQ(found, std::set<int>{0});
    EXPECT_DOUBLE_EQ(shape.contactTree().bounds().max.x(), shape.tree().bounds().max.x() + shape.contactSlack());
    // A third step, then an edit before anything is read: the survivor's hull and the
    // contact tree's kept branch come along where that step put them.
    Eigen::Isometry3d third = Eigen::Isometry3d::Identity();
    third.translation() = Eigen::Vector3d(-4, 0, 0);
    shape.setPrimitivePoses(rest, std::vector<Eigen::Isometry3d>{third, first});
    shape.removePrimitives({1});
    expectHullOn(0);
    EXPECT_DOUBLE_EQ(shape.contactTree().bounds().min.x(), -4.5 - shape.contactSlack());
}

TEST(GroupShape, RemovedPrimitivesLeaveTheRestInOrderWithTheirHulls) {
    // Four unit cubes in a row at x = 0, 2, 4, 6; removing 3 and 1 leaves 0 and 2, in order,
    // with the same child hulls, and trees, bounds and inertia over those two only.
    std::vector<geometry::ConvexPolyhedron> cubes;
    for (int i = 0; i < 4; ++i) cubes.push_back(boxPrimitive({2.0 * i, 0, 0}, {0.5, 0.5, 0.5}));
    GroupShape shape(cubes, 0.01);
    const btConvexHullShape* hull0 = &shape.child(0);
    const btConvexHullShape* hull2 = &shape.child(2);
    shape.removePrimitives({3, 1});
    ASSERT_EQ(shape.primitiveCount(), 2);
    EXPECT_EQ(shape.primitives()[0].vertices(), cubes[0].vertices());
    EXPECT_EQ(shape.primitives()[1].vertices(), cubes[2].vertices());
    EXPECT_EQ(&shape.child(0), hull0);
    EXPECT_EQ(&shape.child(1), hull2);
    for (const geometry::AabbTree* tree : {&shape.tree(), &shape.contactTree()}) {
        EXPECT_EQ(tree->itemCount(), 2);
        std::set<int> found;
        tree->query(geometry::Aabb{{-1, -1, -1}, {7, 1, 1}}, [&](int i) { found.insert(i); });
        EXPECT_EQ(found, (std::set<int>{0, 1}));
        found.clear();
        tree->query(geometry::Aabb{{3.9, -0.1, -0.1}, {4.1, 0.1, 0.1}}, [&](int i) { found.insert(i); });
        EXPECT_EQ(found, std::set<int>{1});
    }
    btVector3 lo, hi;
    shape.getAabb(btTransform::getIdentity(), lo, hi);
    EXPECT_NEAR(hi.x(), 4.51, 1e-6); // the cube at x = 6 is gone from the bounds
    CountTriangles all;
    shape.processAllTriangles(&all, btVector3(-100, -100, -100), btVector3(100, 100, 100));
    EXPECT_EQ(all.primitives, (std::set<int>{0, 1}));
    btVector3 inertia, expected;
    shape.calculateLocalInertia(1.0f, inertia);
    GroupShape({cubes[0], cubes[2]}, 0.01).calculateLocalInertia(1.0f, expected);
    EXPECT_NEAR((inertia - expected).length(), 0.0, 1e-6);
    EXPECT_THROW(shape.removePrimitives({2}), InputError);
    EXPECT_THROW(shape.removePrimitives({0, 1}), InputError); // none would be left
    EXPECT_EQ(shape.primitiveCount(), 2);
}

TEST(GroupShape, ExchangedPrimitivesKeepTheSurvivorsHullsAndAppendThePieces) {
    // Cubes at x = 0, 2, 4; the middle one is exchanged for its two halves (a subdivision):
    // 0 and 4 keep their hulls, the halves come last, and the trees find them there.
    std::vector<geometry::ConvexPolyhedron> cubes;
    for (int i = 0; i < 3; ++i) cubes.push_back(boxPrimitive({2.0 * i, 0, 0}, {0.5, 0.5, 0.5}));
    GroupShape shape(cubes, 0.01);
    const btConvexHullShape* hull0 = &shape.child(0);
    const btConvexHullShape* hull2 = &shape.child(2);
    btVector3 inertiaBefore;
    shape.calculateLocalInertia(1.0f, inertiaBefore);
    shape.removePrimitives({1}, {boxPrimitive({1.75, 0, 0}, {0.25, 0.5, 0.5}), boxPrimitive({2.25, 0, 0}, {0.25, 0.5, 0.5})});
    ASSERT_EQ(shape.primitiveCount(), 4);
    EXPECT_EQ(&shape.child(0), hull0);
    EXPECT_EQ(&shape.child(1), hull2);
    EXPECT_EQ(shape.primitives()[1].vertices(), cubes[2].vertices());
    std::set<int> found;
    shape.tree().query(geometry::Aabb{{2.1, -0.1, -0.1}, {2.2, 0.1, 0.1}}, [&](int i) { found.insert(i); });
    EXPECT_EQ(found, std::set<int>{3});
    btVector3 inertia;
    shape.calculateLocalInertia(1.0f, inertia); // the same mass where it was
    EXPECT_NEAR((inertia - inertiaBefore).length(), 0.0, 1e-5);
    shape.removePrimitives({0, 1, 2, 3}, {cubes[0]}); // all may go when something comes
    EXPECT_EQ(shape.primitiveCount(), 1);
    EXPECT_THROW(shape.removePrimitives({0}, {}), InputError);
}

TEST(GroupShape, FilledPrimitivesTakeTheHolesPlacesWithTheirHullsTreesAndBounds) {
    // Six unit cubes in a row at x = 0, 2, .., 10 lose 1 and 4 and gain fewer, as many and
    // more pieces (small cubes above them) than holes: each primitive sits where
    // geometry::fillHoles puts it, a survivor keeps its own child hull (the same object,
    // moved), and the trees and bounds answer as a shape built from that order does.
    for (const int pieces : {1, 2, 3}) {
        std::vector<geometry::ConvexPolyhedron> cubes, added;
        for (int i = 0; i < 6; ++i) cubes.push_back(boxPrimitive({2.0 * i, 0, 0}, {0.5, 0.5, 0.5}));
        for (int j = 0; j < pieces; ++j) added.push_back(boxPrimitive({2.0 * j + 1, 0, 3}, {0.2, 0.2, 0.2}));
        const std::vector<int> removed = {1, 4};
        GroupShape shape(cubes, 0.01);
        std::vector<const btConvexHullShape*> hull;
        for (int i = 0; i < 6; ++i) hull.push_back(&shape.child(i));
        shape.fillPrimitives(removed, added);

        const geometry::HoleFilling slots = geometry::fillHoles(6, removed, pieces);
        const std::vector<int> to = slots.newIndex(6, removed);
        std::vector<geometry::ConvexPolyhedron> expected(size_t(slots.size), cubes[0]);
        for (int i = 0; i < 6; ++i)
            if (to[size_t(i)] >= 0) expected[size_t(to[size_t(i)])] = cubes[size_t(i)];
        for (int j = 0; j < pieces; ++j) expected[size_t(slots.addedAt[size_t(j)])] = added[size_t(j)];
        const GroupShape fresh(expected, 0.01);
        ASSERT_EQ(shape.primitiveCount(), fresh.primitiveCount()) << pieces;
        for (int i = 0; i < shape.primitiveCount(); ++i) {
            EXPECT_EQ(shape.primitives()[size_t(i)].vertices(), expected[size_t(i)].vertices()) << pieces << " " << i;
            expectSameHull(shape.child(i), fresh.child(i));
        }
        for (int i = 0; i < 6; ++i)
            if (to[size_t(i)] >= 0) {
                EXPECT_EQ(&shape.child(to[size_t(i)]), hull[size_t(i)]) << pieces << " " << i;
            }
        for (const auto& [edited, built] : {std::pair{&shape.tree(), &fresh.tree()}, {&shape.contactTree(), &fresh.contactTree()}}) {
            EXPECT_EQ(edited->itemCount(), built->itemCount());
            EXPECT_EQ(edited->bounds().min, built->bounds().min);
            EXPECT_EQ(edited->bounds().max, built->bounds().max);
            for (int i = 0; i < fresh.primitiveCount(); ++i) {
                std::set<int> found, wanted;
                const geometry::Aabb box = expected[size_t(i)].bounds();
                edited->query(box, [&](int k) { found.insert(k); });
                built->query(box, [&](int k) { wanted.insert(k); });
                EXPECT_EQ(found, wanted) << pieces << " " << i;
            }
        }
        btVector3 lo, hi, freshLo, freshHi;
        shape.getAabb(btTransform::getIdentity(), lo, hi);
        fresh.getAabb(btTransform::getIdentity(), freshLo, freshHi);
        EXPECT_EQ(lo, freshLo);
        EXPECT_EQ(hi, freshHi);
    }
    GroupShape shape({boxPrimitive({0, 0, 0}, {0.5, 0.5, 0.5}), boxPrimitive({2, 0, 0}, {0.5, 0.5, 0.5})}, 0.01);
    EXPECT_THROW(shape.fillPrimitives({1, 0}, {}), InputError);  // not ascending
    EXPECT_THROW(shape.fillPrimitives({2}, {}), InputError);     // out of range
    EXPECT_THROW(shape.fillPrimitives({0, 1}, {}), InputError);  // all of them
    EXPECT_EQ(shape.primitiveCount(), 2);
}

TEST(GroupShape, PiecesFilledFromTheEditedMeshAreTheirMovedCopiesInTheRemovedOnesStorage) {
    // A rest edited in place gives its shape the pieces as the mesh holds them after the same
    // edit, with the mesh-to-shape transform: the shape must be the one fillPrimitives gives
    // with the pieces moved (moved()), bit for bit, and a piece that takes a removed cube's
    // place (with no more vertices) must be written into that cube's storage.
    Eigen::Isometry3d toShape = Eigen::Isometry3d::Identity();
    toShape.rotate(Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()));
    toShape.pretranslate(Eigen::Vector3d(0.1, -0.2, 0.7));
    const std::vector<int> removed = {1, 4};
    for (const int pieces : {1, 2, 3}) {
        std::vector<geometry::ConvexPolyhedron> mesh, inShape, moved;
        for (int i = 0; i < 6; ++i) mesh.push_back(boxPrimitive({2.0 * i, 0, 0}, {0.5, 0.5, 0.5}));
        for (const auto& c : mesh) inShape.push_back(c.moved(toShape));
        const geometry::HoleFilling slots = geometry::fillHoles(6, removed, pieces);
        const std::vector<int> to = slots.newIndex(6, removed);
        std::vector<geometry::ConvexPolyhedron> edited(size_t(slots.size));
        for (int i = 0; i < 6; ++i)
            if (to[size_t(i)] >= 0) edited[size_t(to[size_t(i)])] = mesh[size_t(i)];
        for (int j = 0; j < pieces; ++j) {
            const geometry::ConvexPolyhedron piece = boxPrimitive({2.0 * j + 1, 0, 3}, {0.2, 0.2, 0.2});
            edited[size_t(slots.addedAt[size_t(j)])] = piece;
            moved.push_back(piece.moved(toShape));
        }
        GroupShape byCopies(inShape, 0.01), fromMesh(inShape, 0.01);
        const Eigen::Vector3d* removedStorage = fromMesh.primitives()[1].vertices().data();
        byCopies.fillPrimitives(removed, moved);
        fromMesh.fillPrimitives(removed, edited, pieces, toShape);
        ASSERT_EQ(fromMesh.primitiveCount(), byCopies.primitiveCount());
        for (int i = 0; i < byCopies.primitiveCount(); ++i) {
            const auto& a = fromMesh.primitives()[size_t(i)];
            const auto& b = byCopies.primitives()[size_t(i)];
            EXPECT_EQ(a.vertices(), b.vertices()) << pieces << " " << i;
            EXPECT_EQ(a.globalIds(), b.globalIds());
            ASSERT_EQ(a.planes().size(), b.planes().size());
            for (size_t f = 0; f < a.planes().size(); ++f) {
                EXPECT_EQ(a.planes()[f].normal, b.planes()[f].normal);
                EXPECT_EQ(a.planes()[f].offset, b.planes()[f].offset);
            }
            EXPECT_EQ(a.bounds().min, b.bounds().min);
            EXPECT_EQ(a.bounds().max, b.bounds().max);
            EXPECT_EQ(a.massProperties(1.0).centerOfMass, b.massProperties(1.0).centerOfMass);
            EXPECT_EQ(a.massProperties(1.0).inertia, b.massProperties(1.0).inertia);
            expectSameHull(fromMesh.child(i), byCopies.child(i));
        }
        EXPECT_EQ(fromMesh.primitives()[1].vertices().data(), removedStorage) << pieces; // slot 1 takes piece 0
        for (const auto* shape : {&fromMesh, &byCopies}) {
            std::vector<int> found;
            shape->contactTree().query(geometry::Aabb{{-10, -10, -10}, {30, 10, 10}}, [&](int k) { found.push_back(k); });
            EXPECT_EQ(found.size(), size_t(slots.size));
        }
        btVector3 lo, hi, copiesLo, copiesHi;
        fromMesh.getAabb(btTransform::getIdentity(), lo, hi);
        byCopies.getAabb(btTransform::getIdentity(), copiesLo, copiesHi);
        EXPECT_EQ(lo, copiesLo);
        EXPECT_EQ(hi, copiesHi);
    }
    GroupShape shape({boxPrimitive({0, 0, 0}, {0.5, 0.5, 0.5}), boxPrimitive({2, 0, 0}, {0.5, 0.5, 0.5})}, 0.01);
    const std::vector<geometry::ConvexPolyhedron> tooFew = {boxPrimitive({0, 0, 0}, {0.5, 0.5, 0.5})};
    EXPECT_THROW(shape.fillPrimitives({1}, tooFew, 1, toShape), InputError); // the edit leaves two
    EXPECT_EQ(shape.primitives()[1].vertices(), boxPrimitive({2, 0, 0}, {0.5, 0.5, 0.5}).vertices());
}

TEST(GroupShape, ARemovedPrimitiveNoLongerCollides) {
    // Two balls rest on a static row of two cubes. The second cube is removed, its body out of
    // the world meanwhile (which drops the pairs and their cached algorithms): the ball on it
    // falls through, the other stays.
    GroupWorld w;
    btRigidBody* row =
        w.addStaticGroup({boxPrimitive({0, 0, 0}, {0.5, 0.5, 0.5}), boxPrimitive({2, 0, 0}, {0.5, 0.5, 0.5})},
                         btTransform::getIdentity(), 0.01);
    btRigidBody* stays = w.add(std::make_unique<btSphereShape>(0.2f), 1.0,
                               btTransform(btQuaternion::getIdentity(), btVector3(0, 0.72f, 0)));
    btRigidBody* falls = w.add(std::make_unique<btSphereShape>(0.2f), 1.0,
                               btTransform(btQuaternion::getIdentity(), btVector3(2, 0.72f, 0)));
    w.step(60);
    EXPECT_NEAR(falls->getCenterOfMassPosition().y(), 0.71f, 0.02f);
    const int group = row->getBroadphaseHandle()->m_collisionFilterGroup;
    const int mask = row->getBroadphaseHandle()->m_collisionFilterMask;
    w.world().removeRigidBody(row);
    static_cast<GroupShape*>(row->getCollisionShape())->removePrimitives({1});
    w.world().addRigidBody(row, group, mask);
    w.step(120); // 0.5 s: a free fall of 1.2 m
    EXPECT_NEAR(stays->getCenterOfMassPosition().y(), 0.71f, 0.02f);
    EXPECT_LT(falls->getCenterOfMassPosition().y(), 0.0f);
}

namespace {

// A dispatcher whose double-dispatch tables can be read.
class TableDispatcher : public btCollisionDispatcher {
public:
    using btCollisionDispatcher::btCollisionDispatcher;
    btCollisionAlgorithmCreateFunc* contact(int a, int b) const { return m_doubleDispatchContactPoints[a][b]; }
    btCollisionAlgorithmCreateFunc* closest(int a, int b) const { return m_doubleDispatchClosestPoints[a][b]; }
};

} // namespace

TEST(GroupShapeAlgorithms, RegisterAndUnregisterTouchOnlyGroupAndHullPairs) {
    btDefaultCollisionConfiguration config;
    TableDispatcher dispatcher(&config);
    const auto isDefault = [&](int a, int b) {
        return dispatcher.contact(a, b) == config.getCollisionAlgorithmCreateFunc(a, b) &&
               dispatcher.closest(a, b) == config.getClosestPointsAlgorithmCreateFunc(a, b);
    };
    registerGroupShapeAlgorithms(dispatcher);
    for (int a = 0; a < MAX_BROADPHASE_COLLISION_TYPES; ++a)
        for (int b = 0; b < MAX_BROADPHASE_COLLISION_TYPES; ++b) {
            const bool groupPair = a == kGroupShapeType || b == kGroupShapeType;
            const int other = a == kGroupShapeType ? b : a;
            const bool kept = other == COMPOUND_SHAPE_PROXYTYPE || other == SOFTBODY_SHAPE_PROXYTYPE;
            // Hull-hull contacts go through FragmentPairCreateFunc, which hands pairs without a
            // fragment hull back to the configuration's algorithm (fragment_pair_test.cpp).
            const bool hulls = a == CONVEX_HULL_SHAPE_PROXYTYPE && b == CONVEX_HULL_SHAPE_PROXYTYPE;
            EXPECT_EQ(isDefault(a, b), (!groupPair || kept) && !hulls) << a << "," << b;
        }
    unregisterGroupShapeAlgorithms(dispatcher);
    for (int a = 0; a < MAX_BROADPHASE_COLLISION_TYPES; ++a)
        for (int b = 0; b < MAX_BROADPHASE_COLLISION_TYPES; ++b) EXPECT_TRUE(isDefault(a, b)) << a << "," << b;
}

TEST(GroupShapeAlgorithms, CompoundPairsGoThroughBulletsCompoundAlgorithm) {
    btDefaultCollisionConfiguration config;
    btCollisionDispatcher dispatcher(&config);
    registerGroupShapeAlgorithms(dispatcher);
    GroupShape group({boxPrimitive({0, 0, 0}, {1, 1, 1})}, 0.04);
    btBoxShape box(btVector3(1, 1, 1));
    btCompoundShape compound;
    compound.addChildShape(btTransform::getIdentity(), &box);
    btCollisionObject groupObject, boxObject, compoundObject;
    groupObject.setCollisionShape(&group);
    boxObject.setCollisionShape(&box);
    compoundObject.setCollisionShape(&compound);
    btCollisionObjectWrapper g(nullptr, &group, &groupObject, groupObject.getWorldTransform(), -1, -1);
    btCollisionObjectWrapper b(nullptr, &box, &boxObject, boxObject.getWorldTransform(), -1, -1);
    btCollisionObjectWrapper c(nullptr, &compound, &compoundObject, compoundObject.getWorldTransform(), -1, -1);
    const auto kind = [&](const btCollisionObjectWrapper* x, const btCollisionObjectWrapper* y, ebtDispatcherQueryType t) {
        btCollisionAlgorithm* a = dispatcher.findAlgorithm(x, y, nullptr, t);
        const int k = dynamic_cast<GroupConvexAlgorithm*>(a) ? 1 : dynamic_cast<btCompoundCollisionAlgorithm*>(a) ? 2 : 0;
        a->~btCollisionAlgorithm();
        dispatcher.freeCollisionAlgorithm(a);
        return k;
    };
    for (auto t : {BT_CONTACT_POINT_ALGORITHMS, BT_CLOSEST_POINT_ALGORITHMS}) {
        EXPECT_EQ(kind(&g, &b, t), 1);
        EXPECT_EQ(kind(&b, &g, t), 1);
        EXPECT_EQ(kind(&g, &c, t), 2);
        EXPECT_EQ(kind(&c, &g, t), 2);
    }
}

namespace {

// Primitive i turned by `angle` times (i + 1) about a tilted axis and moved along it.
std::vector<Eigen::Isometry3d> turnedPoses(int count, double angle) {
    std::vector<Eigen::Isometry3d> poses;
    for (int i = 0; i < count; ++i) {
        Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
        pose.linear() = Eigen::AngleAxisd(angle * (i + 1), Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
        pose.translation() = Eigen::Vector3d(0.1 * i, angle, -0.05 * i);
        poses.push_back(pose);
    }
    return poses;
}

} // namespace

TEST(GroupShape, HullsFirstAskedForAfterEditsAreTheHullsAskedForAtOnce) {
    // Hulls are built on first use (child()). One shape's hulls are read at every turn,
    // the other's only at the end: a soft step, a removal with pieces added, another step and
    // a new margin in between must leave the same hulls bit for bit (a hull first built after
    // a step would be built from the moved primitive, not moved from its rest build).
    std::vector<geometry::ConvexPolyhedron> rest;
    for (int i = 0; i < 5; ++i) rest.push_back(boxPrimitive({2.0 * i, 0, 0}, {0.5, 0.3 + 0.05 * i, 0.2}));
    rest[2] = geometry::ConvexPolyhedron::create({{4, 0, 0}, {5, 0, 0}, {4, 1, 0}, {4, 0, 1}},
                                                 {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}}, {0, 1, 2, 3});
    GroupShape eager(rest, 0.01), lazy(rest, 0.01);
    const auto readAll = [](const GroupShape& s) {
        for (int i = 0; i < s.primitiveCount(); ++i) s.child(i);
    };
    readAll(eager);
    eager.setPrimitivePoses(rest, turnedPoses(5, 0.3));
    lazy.setPrimitivePoses(rest, turnedPoses(5, 0.3));
    readAll(eager);
    const std::vector<geometry::ConvexPolyhedron> pieces{boxPrimitive({9, 0, 0}, {0.2, 0.2, 0.2}),
                                                         boxPrimitive({10, 0, 0}, {0.3, 0.2, 0.1})};
    eager.removePrimitives({0, 3}, pieces);
    lazy.removePrimitives({0, 3}, pieces);
    readAll(eager);
    const std::vector<geometry::ConvexPolyhedron> laterRest{rest[1], rest[2], rest[4], pieces[0], pieces[1]};
    eager.setPrimitivePoses(laterRest, turnedPoses(5, 0.7));
    lazy.setPrimitivePoses(laterRest, turnedPoses(5, 0.7));
    eager.setMargin(0.02);
    lazy.setMargin(0.02);
    ASSERT_EQ(lazy.primitiveCount(), 5);
    for (int i = 0; i < 5; ++i) expectSameHull(eager.child(i), lazy.child(i));
    // And a hull of a shape never stepped is the one built over its primitive.
    GroupShape fresh(rest, 0.01);
    const GroupShape single({rest[2]}, 0.01);
    expectSameHull(fresh.child(2), single.child(0));
}

TEST(GroupShape, SoftShapeThatLostPrimitivesMovesLikeOneBuiltFromTheRest) {
    // A soft body's shape (primitives moved by poses each step): after some primitives go, the
    // next step must move the survivors' hulls with their own rest edges, exactly as a shape
    // built from the survivors alone would.
    std::vector<geometry::ConvexPolyhedron> rest;
    for (int i = 0; i < 5; ++i) rest.push_back(boxPrimitive({2.0 * i, 0, 0}, {0.5, 0.3 + 0.05 * i, 0.2}));
    // A tetrahedron: other edges than the boxes'.
    rest[2] = geometry::ConvexPolyhedron::create({{4, 0, 0}, {5, 0, 0}, {4, 1, 0}, {4, 0, 1}},
                                                 {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}}, {0, 1, 2, 3});
    GroupShape shape(rest, 0.01);
    shape.setContactPerPrimitive(true);
    shape.setPrimitivePoses(rest, turnedPoses(5, 0.3));
    shape.removePrimitives({0, 3});
    const std::vector<geometry::ConvexPolyhedron> kept{rest[1], rest[2], rest[4]};
    std::vector<Eigen::Isometry3d> poses = turnedPoses(5, 0.7);
    poses = {poses[1], poses[2], poses[4]};
    shape.setPrimitivePoses(kept, poses);

    GroupShape fresh(kept, 0.01);
    fresh.setPrimitivePoses(kept, poses);
    ASSERT_EQ(shape.primitiveCount(), 3);
    for (int i = 0; i < 3; ++i) {
        EXPECT_EQ(shape.primitives()[size_t(i)].vertices(), fresh.primitives()[size_t(i)].vertices());
        expectSameHull(shape.child(i), fresh.child(i));
    }
    btVector3 lo, hi, freshLo, freshHi;
    shape.getAabb(btTransform::getIdentity(), lo, hi);
    fresh.getAabb(btTransform::getIdentity(), freshLo, freshHi);
    EXPECT_EQ(lo, freshLo);
    EXPECT_EQ(hi, freshHi);
}

namespace {

std::vector<geometry::ConvexPolyhedron> overlappingRest() {
    // Boxes overlapping their neighbours (so the trees report pairs) and a tetrahedron.
    std::vector<geometry::ConvexPolyhedron> rest;
    for (int i = 0; i < 7; ++i) rest.push_back(boxPrimitive({0.3 * i, 0.1 * (i % 3), 0}, {0.2, 0.15 + 0.01 * i, 0.1}));
    rest[3] = geometry::ConvexPolyhedron::create({{0.9, 0, 0}, {1.3, 0, 0}, {0.9, 0.4, 0}, {0.9, 0, 0.3}},
                                                 {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}}, {0, 1, 2, 3});
    return rest;
}

template <class T>
std::vector<T> picked(const std::vector<T>& all, const std::vector<int>& indices) {
    std::vector<T> out;
    for (int i : indices) out.push_back(all[size_t(i)]);
    return out;
}

} // namespace

TEST(GroupShape, TakenPrimitivesMakeTheShapeBuiltFromTheirRestAndPosed) {
    // A torn soft body's new part takes its parent's hulls: the shape must be the one a new
    // body builds from the part's rest primitives and then poses where the parent's are
    // (hulls, inner spheres, trees, box), bit for bit, and the parent what is left once it
    // drops them. The parent was built at another pose than the rest (a body placed in the
    // world), so its hulls' inner spheres came out with other roundings.
    const std::vector<geometry::ConvexPolyhedron> rest = overlappingRest();
    const int n = int(rest.size());
    Eigen::Isometry3d placed = Eigen::Isometry3d::Identity();
    placed.linear() = Eigen::AngleAxisd(0.9, Eigen::Vector3d(3, -1, 2).normalized()).toRotationMatrix();
    placed.translation() = Eigen::Vector3d(12.37, -41.3, 72.1);
    std::vector<geometry::ConvexPolyhedron> atStart;
    for (const auto& p : rest) atStart.push_back(p.transformed(placed));
    GroupShape parent(atStart, 0.01);
    parent.setContactPerPrimitive(true);
    parent.setPrimitivePoses(rest, std::vector<Eigen::Isometry3d>(size_t(n), placed));
    const std::vector<Eigen::Isometry3d> poses = turnedPoses(n, 0.05);
    parent.setPrimitivePoses(rest, poses);

    const std::vector<int> taken{1, 2, 3, 5};
    const std::vector<geometry::ConvexPolyhedron> partRest = picked(rest, taken);
    GroupShape part(parent, taken, partRest);
    GroupShape fresh(partRest, 0.01);
    // Until fitBox, the box is a new shape's, not yet posed (where its body enters the world).
    btVector3 lo, hi, freshLo, freshHi;
    part.getAabb(btTransform::getIdentity(), lo, hi);
    fresh.getAabb(btTransform::getIdentity(), freshLo, freshHi);
    EXPECT_EQ(lo, freshLo);
    EXPECT_EQ(hi, freshHi);
    fresh.setContactPerPrimitive(true);
    fresh.setPrimitivePoses(partRest, picked(poses, taken));
    ASSERT_FALSE(treePairs(fresh.tree()).empty());
    part.fitBox();
    expectSameShape(part, fresh);

    // Slots taken are not there to take again, nor are others out of range; a rest list of
    // another length is an error too.
    EXPECT_THROW(GroupShape(parent, {2}, {rest[2]}), InputError);
    EXPECT_THROW(GroupShape(parent, {n}, {rest[0]}), InputError);
    EXPECT_THROW(GroupShape(parent, {0, 4}, {rest[0]}), InputError);
    EXPECT_THROW(GroupShape(parent, {}, {}), InputError);
    EXPECT_THROW(GroupShape(parent, {4, 4}, {rest[4], rest[4]}), InputError);
    EXPECT_THROW(GroupShape(parent, {6, 0}, {rest[6], rest[0]}), InputError);

    // The parent drops the taken slots and goes on as the rest.
    parent.removePrimitives(taken);
    const std::vector<int> left{0, 4, 6};
    const std::vector<Eigen::Isometry3d> later = turnedPoses(n, 0.08);
    parent.setPrimitivePoses(picked(rest, left), picked(later, left));
    GroupShape leftFresh(picked(atStart, left), 0.01);
    leftFresh.setContactPerPrimitive(true);
    leftFresh.setPrimitivePoses(picked(rest, left), picked(later, left));
    ASSERT_EQ(parent.primitiveCount(), 3);
    for (int i = 0; i < 3; ++i) {
        EXPECT_EQ(parent.primitives()[size_t(i)].vertices(), leftFresh.primitives()[size_t(i)].vertices());
        expectSameHull(parent.child(i), leftFresh.child(i));
    }
}
