// The anchored rest of a broken wall keeps its Bullet body: only the tets that left are taken
// out of its group shape. It must be what a body built from scratch over its tets would be,
// and collide where its tets are and nowhere else.
#include <shatter/bullet_ext/Convert.h>
#include <shatter/bullet_ext/lattice/LatticeBody.h>
#include <shatter/bullet_ext/VisualBody.h>
#include "tests/bullet_ext/lattice/WallScene.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace shatter {
namespace {

using test::WallScene;

// The anchored piece with the most tets.
const LatticeBody::Piece& anchoredRest(const LatticeBody& wall) {
    const LatticeBody::Piece* rest = nullptr;
    for (const auto& p : wall.pieces())
        if (p.lattice.anchored && (!rest || p.lattice.particles.size() > rest->lattice.particles.size())) rest = &p;
    return *rest;
}

TEST(LatticeRemainder, TheAnchoredRestKeepsItsBodyAndMatchesARebuild) {
    WallScene s(8.0);
    VisualBody* original = s.wall->pieces()[0].body;
    const btRigidBody* rigid = &original->rigidBody();
    s.w.step(60);
    const LatticeBody& wall = *s.wall;
    ASSERT_GT(wall.pieceCount(), 5);
    const LatticeBody::Piece& rest = anchoredRest(wall);
    const std::vector<int>& tets = rest.lattice.particles;
    ASSERT_LT(int(tets.size()), wall.tetCount());
    EXPECT_EQ(rest.body, original);
    EXPECT_EQ(&rest.body->rigidBody(), rigid);
    EXPECT_EQ(rest.body->name(), "wall");
    EXPECT_EQ(rigid->getInvMass(), 0); // static, as it was

    const geometry::PhysicalMesh rebuilt = wall.physicalMesh(tets, "wall");
    EXPECT_EQ(rest.mass.mass, rebuilt.mass.mass); // the same sums over the same tets: exact
    EXPECT_EQ(rest.mass.centerOfMass, rebuilt.mass.centerOfMass);
    EXPECT_EQ(rest.mass.inertia, rebuilt.mass.inertia);
    const geometry::PhysicalMesh& mesh = rest.body->physicalMesh();
    EXPECT_EQ(mesh.mass.mass, rebuilt.mass.mass);
    // The same faces (outer surface and every crack face) at the same nodes; the kept body
    // numbers its visual vertices as when it was whole.
    const Eigen::Isometry3d meshToWorld = toEigen(rest.body->meshTransform());
    const geometry::VisualMesh& visual = rest.body->visualMesh();
    EXPECT_EQ(visual.faces, mesh.visual.faces);
    ASSERT_EQ(mesh.visual.faces.size(), rebuilt.visual.faces.size());
    for (size_t f = 0; f < rebuilt.visual.faces.size(); ++f) {
        ASSERT_EQ(mesh.visual.faces[f].size(), 3u);
        for (int c = 0; c < 3; ++c) {
            const Eigen::Vector3d& node = rebuilt.visual.positions[rebuilt.visual.faces[f][c]];
            EXPECT_EQ(mesh.visual.positions[mesh.visual.faces[f][c]], node);
            // What the application draws: the new surface, where the wall stands.
            EXPECT_LT((visual.positions[mesh.visual.faces[f][c]] - meshToWorld * node).norm(), 1e-5);
        }
    }
    ASSERT_EQ(mesh.primitives.size(), tets.size());
    const GroupShape& shape = rest.body->shape();
    ASSERT_EQ(shape.primitiveCount(), int(tets.size()));
    // Primitive i is still tet i of the sorted list (contacts name it), in the body frame,
    // and its child hull is that tet's.
    for (size_t i = 0; i < tets.size(); ++i) {
        const auto expected = rebuilt.primitives[i].transformed(rest.body->meshToBody()).vertices();
        const auto& actual = shape.primitives()[i].vertices();
        ASSERT_EQ(actual.size(), expected.size());
        for (size_t k = 0; k < actual.size(); ++k) {
            EXPECT_LT((actual[k] - expected[k]).norm(), 1e-12) << "tet " << tets[i];
            EXPECT_LT((toEigen(shape.child(int(i)).getUnscaledPoints()[k]) - expected[k]).norm(), 1e-6);
        }
    }
    EXPECT_EQ(shape.tree().itemCount(), int(tets.size()));
    // Visual vertices of tets that left are no face's any more, but stay where they were.
    ASSERT_EQ(visual.positions.size(), mesh.visual.positions.size());
    for (size_t j = 0; j < visual.positions.size(); ++j)
        EXPECT_LT((visual.positions[j] - meshToWorld * mesh.visual.positions[j]).norm(), 1e-5) << "vertex " << j;
}

// Deepest penetration (m, negative) of a small ball at `centre` into `body`, 0 if none.
double penetration(btCollisionWorld& world, btCollisionObject& body, const Eigen::Vector3d& centre, double radius) {
    btSphereShape ballShape{btScalar(radius)};
    btCollisionObject ball;
    ball.setCollisionShape(&ballShape);
    ball.setWorldTransform(btTransform(btQuaternion::getIdentity(), toBullet(centre)));
    struct Deepest : btCollisionWorld::ContactResultCallback {
        double depth = 0.0;
        btScalar addSingleResult(btManifoldPoint& p, const btCollisionObjectWrapper*, int, int,
                                 const btCollisionObjectWrapper*, int, int) override {
            depth = std::min(depth, double(p.getDistance()));
            return 0;
        }
    } deepest;
    world.contactPairTest(&ball, &body, deepest);
    return deepest.depth;
}

// Distance from a tet's centroid to its nearest face plane (m, mesh coordinates).
double centroidDepth(const lattice::TetMesh& mesh, int tet, Eigen::Vector3d& centroid) {
    const lattice::Tet& t = mesh.tets[tet];
    centroid = Eigen::Vector3d::Zero();
    for (int n : t) centroid += 0.25 * mesh.nodes[n];
    double depth = INFINITY;
    for (int f = 0; f < 4; ++f) {
        const Eigen::Vector3d& a = mesh.nodes[t[(f + 1) % 4]];
        const Eigen::Vector3d n = (mesh.nodes[t[(f + 2) % 4]] - a).cross(mesh.nodes[t[(f + 3) % 4]] - a).normalized();
        depth = std::min(depth, std::abs(n.dot(centroid - a)));
    }
    return depth;
}

TEST(LatticeRemainder, ABallHitsTheRestWhereItsTetsAreAndPassesWhereTheyLeft) {
    WallScene s(12.0);
    s.w.step(60);
    const LatticeBody& wall = *s.wall;
    const LatticeBody::Piece& rest = anchoredRest(wall);
    ASSERT_LT(int(rest.lattice.particles.size()), wall.tetCount());
    btRigidBody& body = rest.body->rigidBody();
    const Eigen::Isometry3d meshToWorld = toEigen(rest.body->meshTransform());
    const double radius = 0.002, reach = radius + wall.settings().rigidBody.collisionMargin;
    int hit = 0, passed = 0;
    for (int t = 0; t < wall.tetCount(); ++t) {
        Eigen::Vector3d centroid;
        // Deep enough inside its tet that the ball reaches no other one (tets do not overlap).
        if (centroidDepth(wall.lattice().mesh(), t, centroid) < 2 * reach) continue;
        const double depth = penetration(s.w.world, body, meshToWorld * centroid, radius);
        if (rest.lattice.contains(t)) {
            EXPECT_LT(depth, -radius) << "tet " << t << " of the rest";
            ++hit;
        } else {
            EXPECT_EQ(depth, 0.0) << "tet " << t << " left the rest";
            ++passed;
        }
    }
    EXPECT_GT(hit, 100);
    EXPECT_GT(passed, 10);
}

// A fragment's primitives are copied from the piece it broke off (LatticeBody::partMesh): its
// physical mesh must be the one built from scratch over its tets, bit for bit.
TEST(LatticeRemainder, EveryFragmentsMeshIsTheOneBuiltFromItsTets) {
    WallScene s(8.0);
    s.w.step(60);
    const LatticeBody& wall = *s.wall;
    ASSERT_GT(wall.pieceCount(), 5);
    for (const auto& piece : wall.pieces()) {
        const geometry::PhysicalMesh& mesh = piece.body->physicalMesh();
        const geometry::PhysicalMesh rebuilt = wall.physicalMesh(piece.lattice.particles, mesh.name);
        EXPECT_EQ(mesh.sourceFace, rebuilt.sourceFace);
        EXPECT_EQ(mesh.mass.mass, rebuilt.mass.mass);
        EXPECT_EQ(mesh.mass.inertia, rebuilt.mass.inertia);
        ASSERT_EQ(mesh.primitives.size(), rebuilt.primitives.size());
        for (size_t i = 0; i < mesh.primitives.size(); ++i) {
            const geometry::ConvexPolyhedron& a = mesh.primitives[i];
            const geometry::ConvexPolyhedron& b = rebuilt.primitives[i];
            EXPECT_EQ(a.vertices(), b.vertices());
            // Its vertex ids name its visual vertices (a piece that kept its body after a later
            // break numbers them as when it was made, so the ids themselves may differ).
            for (size_t k = 0; k < a.vertices().size(); ++k)
                EXPECT_EQ(mesh.visual.positions[size_t(a.globalIds()[k])], a.vertices()[k]);
            EXPECT_EQ(a.volume(), b.volume());
            EXPECT_EQ(a.centerOfMass(), b.centerOfMass());
            ASSERT_EQ(a.planes().size(), b.planes().size());
            for (size_t k = 0; k < a.planes().size(); ++k) {
                EXPECT_EQ(a.planes()[k].normal, b.planes()[k].normal);
                EXPECT_EQ(a.planes()[k].offset, b.planes()[k].offset);
            }
        }
    }
}

} // namespace
} // namespace shatter
