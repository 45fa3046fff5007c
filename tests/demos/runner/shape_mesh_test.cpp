// Plain Bullet shapes must come out as closed, outward-facing surfaces of the right size,
// or the frame files and pictures would misrepresent the balls and walls of a scene.
#include "demos/runner/ShapeMesh.h"

#include <shatter/plugin/common/InputError.h>

#include <BulletCollision/CollisionShapes/btBoxShape.h>
#include <BulletCollision/CollisionShapes/btCapsuleShape.h>
#include <BulletCollision/CollisionShapes/btCompoundShape.h>
#include <BulletCollision/CollisionShapes/btConvexHullShape.h>
#include <BulletCollision/CollisionShapes/btCylinderShape.h>
#include <BulletCollision/CollisionShapes/btSphereShape.h>
#include <BulletCollision/CollisionShapes/btStaticPlaneShape.h>

#include <gtest/gtest.h>

#include <map>
#include <numbers>

using namespace shatter;
using namespace shatter::demo;

namespace {

constexpr double kPi = std::numbers::pi;

// Divergence theorem over fan triangles: positive for outward-facing faces.
double signedVolume(const geometry::VisualMesh& m) {
    double v = 0;
    for (const auto& f : m.faces)
        for (size_t i = 1; i + 1 < f.size(); ++i)
            v += m.positions[f[0]].dot(m.positions[f[i]].cross(m.positions[f[i + 1]])) / 6.0;
    return v;
}

// Closed and consistently oriented: every directed edge once, and its reverse once.
bool closedAndOriented(const geometry::VisualMesh& m) {
    std::map<std::pair<int, int>, int> edges;
    for (const auto& f : m.faces)
        for (size_t i = 0; i < f.size(); ++i) ++edges[{f[i], f[(i + 1) % f.size()]}];
    for (const auto& [edge, count] : edges)
        if (count != 1 || edges.count({edge.second, edge.first}) == 0) return false;
    return !edges.empty();
}

Eigen::Vector3d extent(const geometry::VisualMesh& m) {
    Eigen::Vector3d lo = m.positions[0], hi = m.positions[0];
    for (const auto& p : m.positions) {
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
    }
    return hi - lo;
}

} // namespace

TEST(DemoShapeMesh, BoxIsClosedWithItsVolumeAndSixQuads) {
    btBoxShape box(btVector3(0.5, 1.0, 1.5));
    const ShapeMesh s = tessellate(box, "crate");
    EXPECT_FALSE(s.round);
    EXPECT_EQ(s.mesh.positions.size(), 8u);
    ASSERT_EQ(s.mesh.faces.size(), 6u);
    for (const auto& f : s.mesh.faces) EXPECT_EQ(f.size(), 4u);
    EXPECT_TRUE(closedAndOriented(s.mesh));
    EXPECT_NEAR(signedVolume(s.mesh), 1.0 * 2.0 * 3.0, 1e-5);
}

TEST(DemoShapeMesh, SphereIsInscribedAndCloseToTheExactVolume) {
    const double r = 0.5;
    btSphereShape sphere{btScalar(r)};
    const ShapeMesh s = tessellate(sphere, "ball");
    EXPECT_TRUE(s.round);
    EXPECT_TRUE(closedAndOriented(s.mesh));
    for (const auto& p : s.mesh.positions) EXPECT_NEAR(p.norm(), r, 1e-6);
    const double exact = 4.0 / 3.0 * kPi * r * r * r, v = signedVolume(s.mesh);
    EXPECT_LT(v, exact); // vertices on the sphere: the polyhedron is inside it
    EXPECT_GT(v, 0.97 * exact);
}

TEST(DemoShapeMesh, CapsuleFollowsItsAxisAndVolume) {
    const double r = 0.25, half = 0.5;
    btCapsuleShapeX capsule(btScalar(r), btScalar(2 * half));
    const ShapeMesh s = tessellate(capsule, "pill");
    EXPECT_TRUE(closedAndOriented(s.mesh));
    const Eigen::Vector3d e = extent(s.mesh);
    EXPECT_NEAR(e.x(), 2 * (half + r), 1e-6);
    EXPECT_NEAR(e.y(), 2 * r, 1e-2);
    EXPECT_NEAR(e.z(), 2 * r, 1e-2);
    const double exact = kPi * r * r * 2 * half + 4.0 / 3.0 * kPi * r * r * r;
    EXPECT_NEAR(signedVolume(s.mesh), exact, 0.03 * exact);
}

TEST(DemoShapeMesh, CylinderAlongZHasItsVolume) {
    btCylinderShapeZ cylinder(btVector3(0.3f, 0.3f, 0.8f));
    const ShapeMesh s = tessellate(cylinder, "pipe");
    EXPECT_TRUE(closedAndOriented(s.mesh));
    EXPECT_NEAR(extent(s.mesh).z(), 1.6, 1e-5);
    const double exact = kPi * 0.09 * 1.6;
    EXPECT_NEAR(signedVolume(s.mesh), exact, 0.01 * exact);
}

TEST(DemoShapeMesh, ConvexHullDropsInnerPointsAndKeepsTheVolume) {
    btConvexHullShape hull;
    for (int i = 0; i < 8; ++i) hull.addPoint(btVector3(i & 1 ? 1 : -1, i & 2 ? 0.5f : -0.5f, i & 4 ? 2 : -2), false);
    hull.addPoint(btVector3(0.1f, 0.1f, 0.1f), true); // inside
    const ShapeMesh s = tessellate(hull, "rock");
    EXPECT_FALSE(s.round);
    EXPECT_EQ(s.mesh.positions.size(), 8u);
    EXPECT_TRUE(closedAndOriented(s.mesh));
    EXPECT_NEAR(signedVolume(s.mesh), 2.0 * 1.0 * 4.0, 1e-4);
}

TEST(DemoShapeMesh, CompoundPlacesItsChildren) {
    btBoxShape box(btVector3(0.5, 0.5, 0.5));
    btSphereShape ball(0.5);
    btCompoundShape compound;
    compound.addChildShape(btTransform(btQuaternion::getIdentity(), btVector3(-2, 0, 0)), &box);
    compound.addChildShape(btTransform(btQuaternion::getIdentity(), btVector3(2, 0, 0)), &ball);
    const ShapeMesh s = tessellate(compound, "dumbbell");
    EXPECT_FALSE(s.round); // one faceted child is enough for edges to help
    EXPECT_TRUE(closedAndOriented(s.mesh));
    EXPECT_NEAR(extent(s.mesh).x(), 5.0, 1e-5);
    EXPECT_NEAR(signedVolume(s.mesh), 1.0 + 4.0 / 3.0 * kPi * 0.125, 0.03);
}

TEST(DemoShapeMesh, TransformedMovesEveryVertex) {
    btBoxShape box(btVector3(1, 1, 1));
    const ShapeMesh s = tessellate(box, "crate");
    const btTransform t(btQuaternion(btVector3(0, 1, 0), btScalar(kPi / 2)), btVector3(5, 6, 7));
    const auto moved = transformed(s.mesh, t);
    ASSERT_EQ(moved.positions.size(), s.mesh.positions.size());
    EXPECT_EQ(moved.faces, s.mesh.faces);
    for (size_t i = 0; i < moved.positions.size(); ++i)
        EXPECT_NEAR((moved.positions[i] - Eigen::Vector3d(5, 6, 7)).norm(), s.mesh.positions[i].norm(), 1e-5);
    EXPECT_NEAR(signedVolume(moved), 8.0, 1e-4); // a rotation keeps volume and orientation
}

TEST(DemoShapeMesh, UndrawableShapeIsAnErrorNamingTheBody) {
    btStaticPlaneShape plane(btVector3(0, 1, 0), 0);
    try {
        tessellate(plane, "floor2");
        FAIL() << "expected InputError";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("floor2"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("STATICPLANE"), std::string::npos) << e.what();
    }
}
