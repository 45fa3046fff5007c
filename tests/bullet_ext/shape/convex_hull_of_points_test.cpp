// The hull of a fracture shard built from its own faces (convexHullOf + buildPolyhedralFeatures)
// against Bullet's initializePolyhedralFeatures over the same points: the same vertices, faces,
// planes and edge directions (up to order and float rounding), interior objects that are inside, and the same
// contacts against a box.
#include <shatter/bullet_ext/Convert.h>
#include <shatter/bullet_ext/shape/ConvexHullOfPoints.h>
#include <shatter/bullet_ext/shape/HullFeatures.h>
#include <shatter/plugin/common/InputError.h>

#include <btBulletCollisionCommon.h>
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <random>

namespace shatter {
namespace {

// Points of a curved shard: two layers of a cylindrical wall (radius 1 and 0.99) over `sectors`
// sectors of 8° and `rows` rows, like the corners of a vase's extruded quads cut by a cell.
// Top, bottom, side and outer faces are shared by several quads.
std::vector<Eigen::Vector3d> curvedShard(int sectors, int rows) {
    std::vector<Eigen::Vector3d> points;
    for (double r : {1.0, 0.99})
        for (int s = 0; s <= sectors; ++s)
            for (int z = 0; z <= rows; ++z) {
                const double a = 8.0 * s * M_PI / 180.0;
                points.emplace_back(r * std::cos(a), r * std::sin(a), 0.05 * z);
            }
    return points;
}

// Random points in a ball, some of them on a flat cut (z = 0.3) as crack faces have.
std::vector<Eigen::Vector3d> randomPiece(std::mt19937& rng) {
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    std::vector<Eigen::Vector3d> points;
    while (points.size() < 60) {
        Eigen::Vector3d p(u(rng), u(rng), u(rng));
        if (p.norm() > 1.0) continue;
        if (p.z() > 0.3) p.z() = 0.3;
        points.push_back(0.1 * p + Eigen::Vector3d(2.0, -1.0, 0.5));
    }
    return points;
}

// Bullet's own hull over the points (as the fracture system built it before).
std::unique_ptr<btConvexHullShape> bulletHull(const std::vector<Eigen::Vector3d>& points) {
    auto hull = std::make_unique<btConvexHullShape>();
    for (const auto& p : points) hull->addPoint(toBullet(p), false);
    hull->setMargin(0.001f);
    hull->recalcLocalAabb();
    hull->initializePolyhedralFeatures();
    return hull;
}

// The hull built from its faces, with its vertices as points.
std::unique_ptr<btConvexHullShape> facesHull(const std::vector<Eigen::Vector3d>& points) {
    const geometry::ConvexPolyhedron shape = convexHullOf(points);
    auto hull = std::make_unique<btConvexHullShape>();
    for (const auto& v : shape.vertices()) hull->addPoint(toBullet(v), false);
    hull->setMargin(0.001f);
    hull->recalcLocalAabb();
    btConvexPolyhedron features;
    buildPolyhedralFeatures(shape, features);
    hull->setPolyhedralFeatures(features);
    return hull;
}

Eigen::Vector3d normalOf(const btFace& f) { return Eigen::Vector3d(f.m_plane[0], f.m_plane[1], f.m_plane[2]); }

// Every face of `a` is a face of `b`: the same corners, and each lies on the other's plane.
// Bullet's corners are its hull computer's grid points, up to 2.4e-5 m from the input points
// for these pieces, and its normal is the cross product of the first two edges in float (up
// to 1.4e-2 off for the sliver faces of a random piece, its plane through the innermost corner):
// corners agree to 1e-4 m, normals to 2e-2 and corners lie within `planeTolerance` (m) of
// the other's plane.
void expectFacesIn(const btConvexPolyhedron& a, const btConvexPolyhedron& b, double planeTolerance) {
    auto near = [](const btVector3& p, const btConvexPolyhedron& poly, const btFace& face) {
        for (int l = 0; l < face.m_indices.size(); ++l)
            if ((p - poly.m_vertices[face.m_indices[l]]).length() < 1e-4) return true;
        return false;
    };
    for (int i = 0; i < a.m_faces.size(); ++i) {
        const btFace& fa = a.m_faces[i];
        int match = -1;
        for (int j = 0; j < b.m_faces.size() && match < 0; ++j) {
            const btFace& fb = b.m_faces[j];
            bool same = fa.m_indices.size() == fb.m_indices.size();
            for (int k = 0; k < fa.m_indices.size() && same; ++k) same = near(a.m_vertices[fa.m_indices[k]], b, fb);
            if (same) match = j;
        }
        ASSERT_GE(match, 0) << "face " << i << " has no face of the same corners";
        const btFace& fb = b.m_faces[match];
        EXPECT_LT((normalOf(fa) - normalOf(fb)).norm(), 2e-2) << "face " << i;
        for (int k = 0; k < fa.m_indices.size(); ++k) {
            const btVector3& p = a.m_vertices[fa.m_indices[k]];
            EXPECT_LT(std::abs(normalOf(fb).dot(toEigen(p)) + fb.m_plane[3]), planeTolerance) << "face " << i;
        }
    }
}

// Every edge direction of `a` is one of `b`'s, up to sign.
void expectEdgesIn(const btConvexPolyhedron& a, const btConvexPolyhedron& b) {
    for (int i = 0; i < a.m_uniqueEdges.size(); ++i) {
        bool found = false;
        for (int j = 0; j < b.m_uniqueEdges.size() && !found; ++j)
            found = std::abs(std::abs(a.m_uniqueEdges[i].dot(b.m_uniqueEdges[j])) - 1.0) < 1e-5;
        EXPECT_TRUE(found) << "edge " << i;
    }
}

// Faces counter-clockwise from outside, every vertex behind every face, and the inner sphere
// and box Bullet's separating-axis test skips axes with inside the hull.
void expectValid(const btConvexPolyhedron& p) {
    for (int i = 0; i < p.m_faces.size(); ++i) {
        const btFace& f = p.m_faces[i];
        btVector3 newell(0, 0, 0);
        for (int k = 0; k < f.m_indices.size(); ++k) {
            const btVector3& a = p.m_vertices[f.m_indices[k]];
            const btVector3& b = p.m_vertices[f.m_indices[(k + 1) % f.m_indices.size()]];
            newell += a.cross(b);
        }
        EXPECT_GT(toEigen(newell).normalized().dot(normalOf(f)), 0.999) << "face " << i;
        const btVector3 n(f.m_plane[0], f.m_plane[1], f.m_plane[2]);
        for (int v = 0; v < p.m_vertices.size(); ++v) EXPECT_LT(n.dot(p.m_vertices[v]) + f.m_plane[3], 1e-6) << i;
        EXPECT_LE(n.dot(p.m_localCenter) + f.m_plane[3], -p.m_radius + 1e-6) << "inner sphere, face " << i;
        for (int corner = 0; corner < 8; ++corner) {
            const btVector3 c = p.m_localCenter + btVector3(corner & 1 ? p.m_extents[0] : -p.m_extents[0],
                                                            corner & 2 ? p.m_extents[1] : -p.m_extents[1],
                                                            corner & 4 ? p.m_extents[2] : -p.m_extents[2]);
            EXPECT_LE(n.dot(c) + f.m_plane[3], 1e-6) << "inner box, face " << i;
        }
    }
    EXPECT_GT(p.m_radius, 0.0f);
}

void expectSameFeatures(const std::vector<Eigen::Vector3d>& points) {
    const auto bullet = bulletHull(points);
    const auto faces = facesHull(points);
    const btConvexPolyhedron& b = *bullet->getConvexPolyhedron();
    const btConvexPolyhedron& f = *faces->getConvexPolyhedron();
    EXPECT_EQ(f.m_vertices.size(), b.m_vertices.size());
    EXPECT_EQ(f.m_faces.size(), b.m_faces.size());
    expectFacesIn(b, f, 1e-4); // Bullet's corners on the faces here
    expectFacesIn(f, f, 1e-6); // the faces here are flat to float rounding (each its own match)
    expectEdgesIn(f, b);
    expectEdgesIn(b, f);
    expectValid(f);
}

TEST(ConvexHullOfPoints, RandomPiecesHaveBulletsFacesPlanesAndEdges) {
    std::mt19937 rng(7);
    for (int piece = 0; piece < 20; ++piece) {
        SCOPED_TRACE(piece);
        expectSameFeatures(randomPiece(rng));
    }
}

TEST(ConvexHullOfPoints, ACurvedShardHasBulletsFaces) {
    const std::vector<Eigen::Vector3d> points = curvedShard(5, 4);
    const geometry::ConvexPolyhedron hull = convexHullOf(points);
    // Outer wall: one face per sector (its rows are coplanar); chord inside; top, bottom and
    // the two side cuts: 5 + 1 + 2 + 2 = 10.
    EXPECT_EQ(hull.faces().size(), 10u);
    expectSameFeatures(points);
}

TEST(ConvexHullOfPoints, VerticesAreTheInputPointsBitForBit) {
    std::mt19937 rng(3);
    const std::vector<Eigen::Vector3d> points = randomPiece(rng);
    const geometry::ConvexPolyhedron hull = convexHullOf(points);
    for (size_t i = 0; i < hull.vertices().size(); ++i)
        EXPECT_EQ(hull.vertices()[i], points[size_t(hull.globalIds()[i])]);
}

// Contacts of a box pressed into each hull at random poses: the same deepest point's depth and
// normal.
TEST(ConvexHullOfPoints, ContactsAgainstABoxAreBullets) {
    btDefaultCollisionConfiguration config;
    btCollisionDispatcher dispatcher(&config);
    btDbvtBroadphase broadphase;
    btCollisionWorld world(&dispatcher, &broadphase, &config);
    btBoxShape box(btVector3(0.05f, 0.05f, 0.05f));
    box.setMargin(0.001f);
    struct Deepest : btCollisionWorld::ContactResultCallback {
        double depth = 1.0;
        Eigen::Vector3d normal = Eigen::Vector3d::Zero();
        btScalar addSingleResult(btManifoldPoint& cp, const btCollisionObjectWrapper*, int, int,
                                 const btCollisionObjectWrapper*, int, int) override {
            if (cp.getDistance() < depth) {
                depth = cp.getDistance();
                normal = toEigen(cp.m_normalWorldOnB);
            }
            return 0;
        }
    };
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    int touching = 0;
    for (int piece = 0; piece < 10; ++piece) {
        const std::vector<Eigen::Vector3d> points = piece % 2 ? randomPiece(rng) : curvedShard(3 + piece, 3);
        const auto bullet = bulletHull(points);
        const auto faces = facesHull(points);
        Eigen::Vector3d centre = Eigen::Vector3d::Zero();
        for (const auto& p : points) centre += p / double(points.size());
        for (int pose = 0; pose < 10; ++pose) {
            const Eigen::Vector3d dir = Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized();
            const Eigen::Vector3d far = convexHullOf(points).support(dir);
            btCollisionObject boxObject;
            boxObject.setCollisionShape(&box);
            boxObject.setWorldTransform(btTransform(btQuaternion(u(rng), u(rng), u(rng), 1.0).normalized(),
                                                    toBullet(Eigen::Vector3d(far + 0.03 * dir))));
            Deepest withBullet, withFaces;
            btCollisionObject hull;
            hull.setCollisionShape(bullet.get());
            world.contactPairTest(&hull, &boxObject, withBullet);
            hull.setCollisionShape(faces.get());
            world.contactPairTest(&hull, &boxObject, withFaces);
            ASSERT_EQ(withBullet.depth < 0.0, withFaces.depth < 0.0) << piece << " " << pose;
            if (withBullet.depth >= 0.0) continue;
            ++touching;
            EXPECT_NEAR(withFaces.depth, withBullet.depth, 2e-5) << piece << " " << pose;
            EXPECT_GT(withFaces.normal.dot(withBullet.normal), 1.0 - 1e-4) << piece << " " << pose;
        }
    }
    EXPECT_GT(touching, 50); // the test compares contacts, not misses
}

TEST(ConvexHullOfPoints, PointsInOnePlaneAreRejected) {
    const std::vector<Eigen::Vector3d> flat = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {0.5, 0.5, 0}};
    EXPECT_THROW(convexHullOf(flat), InputError);
    EXPECT_THROW(convexHullOf({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}), InputError);
}

} // namespace
} // namespace shatter
