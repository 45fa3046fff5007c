// Buried tets (BuriedTets.h, LatticeSettings::skipBuriedTets): which tets have no corner on a
// piece's surface, that the anchored rest of a breaking body keeps them flagged as it sheds
// tets, and that leaving them out of the contacts changes nothing a body resting on it feels.
#include <shatter/bullet_ext/lattice/BuriedTets.h>
#include <shatter/bullet_ext/lattice/LatticeBody.h>
#include <shatter/bullet_ext/Plugin.h>
#include <shatter/bullet_ext/VisualBody.h>
#include <shatter/bullet_ext/shape/GroupShape.h>
#include <shatter/plugin/lattice/Fragments.h>
#include <shatter/plugin/lattice/TetGenerators.h>
#include "tests/support/TestWorld.h"

#include <gtest/gtest.h>

#include <memory>
#include <set>

namespace shatter {
namespace {

// Tet t of `particles` has no node on a face of lattice::surfaceFaces(particles).
std::vector<char> expectedBuried(const lattice::Lattice& lattice, const std::vector<int>& particles) {
    std::set<int> surfaceNodes;
    for (const auto& face : lattice::surfaceFaces(lattice, particles)) surfaceNodes.insert(face.begin(), face.end());
    std::vector<char> buried;
    for (int t : particles) {
        bool inside = true;
        for (int n : lattice.mesh().tets[t]) inside = inside && !surfaceNodes.count(n);
        buried.push_back(inside);
    }
    return buried;
}

const GroupShape* collisionGroup(const LatticeBody::Piece& piece) {
    return dynamic_cast<const GroupShape*>(piece.body->rigidBody().getCollisionShape());
}

TEST(BuriedTets, OnlyTheTetsOfTheInnerCellsOfABoxAreBuried) {
    // 3 × 3 × 3 cells of 0.1 m: only the middle cell's nodes are all inside the box.
    const lattice::TetMesh mesh = lattice::tetBox({0.3, 0.3, 0.3}, {3, 3, 3});
    LatticeSettings s;
    const LatticeBody body(0, mesh, s);
    std::vector<int> all(body.tetCount());
    for (int i = 0; i < body.tetCount(); ++i) all[i] = i;
    const std::vector<char> buried = buriedPrimitives(body.physicalMesh(all, "box"));
    ASSERT_EQ(int(buried.size()), body.tetCount());
    int count = 0;
    for (int t = 0; t < body.tetCount(); ++t) {
        bool inner = true; // every corner off the box's faces
        for (int n : mesh.tets[t])
            for (int k = 0; k < 3; ++k) inner = inner && std::abs(mesh.nodes[n][k]) < 0.15 - 1e-9;
        EXPECT_EQ(bool(buried[t]), inner) << "tet " << t;
        count += buried[t];
    }
    EXPECT_EQ(count, body.tetCount() / 27); // the middle cell's tets
}

TEST(BuriedTets, TheAnchoredRestKeepsItsBuriedTetsFlaggedAsItSheds) {
    // A thick anchored block (4 cells deep) broken by a ball: after every step, the rest's
    // group shape flags exactly the tets with no corner on the rest's surface (those next to
    // the crater come up as it opens).
    test::TestWorld w;
    w.addGround();
    Plugin plugin(w.world);
    lattice::GeneratorOptions g;
    g.jitter = 0.15;
    const lattice::TetMesh mesh = lattice::tetBox({0.8, 0.6, 0.4}, {8, 6, 4}, g);
    LatticeSettings s;
    s.fixedTets = lattice::tetsWithFaceOnPlane(mesh, {0, 1, 0}, -0.3, 1e-9);
    LatticeBody& block = plugin.addLatticeBody(mesh, s, btTransform(btQuaternion::getIdentity(), btVector3(0, 0.3f, 0)));
    btSphereShape ballShape(0.15f);
    btVector3 inertia;
    ballShape.calculateLocalInertia(60, inertia);
    btRigidBody ball(60, nullptr, &ballShape, inertia);
    ball.setWorldTransform(btTransform(btQuaternion::getIdentity(), btVector3(0, 0.3f, 0.5f)));
    ball.setLinearVelocity(btVector3(0, 0, -10));
    w.world.addRigidBody(&ball);
    int buriedAtStart = 0, shrinks = 0;
    size_t lastSize = block.pieces()[0].lattice.particles.size();
    for (int step = 0; step < 40; ++step) {
        w.step(1);
        for (const auto& piece : block.pieces()) {
            if (!piece.lattice.anchored) continue;
            const GroupShape* group = collisionGroup(piece);
            ASSERT_NE(group, nullptr);
            const std::vector<char> expected = expectedBuried(block.lattice(), piece.lattice.particles);
            ASSERT_EQ(group->primitiveCount(), int(expected.size()));
            int buried = 0;
            for (int i = 0; i < group->primitiveCount(); ++i) {
                EXPECT_EQ(group->buried(i), bool(expected[i])) << "step " << step << ", tet " << piece.lattice.particles[i];
                buried += expected[i];
            }
            if (step == 0) buriedAtStart = buried;
            if (piece.lattice.particles.size() < lastSize) ++shrinks, lastSize = piece.lattice.particles.size();
        }
    }
    w.world.removeRigidBody(&ball);
    EXPECT_GT(buriedAtStart, 100); // the two middle layers, but for the rim
    EXPECT_GT(shrinks, 0);         // the rest did shed tets
}

// A 0.25 m box dropped flat onto a thick anchored block: where it comes to rest.
btVector3 restingBoxOnBlock(bool skipBuried) {
    test::TestWorld w;
    Plugin plugin(w.world);
    const lattice::TetMesh mesh = lattice::tetBox({0.6, 0.4, 0.6}, {6, 4, 6});
    LatticeSettings s;
    s.skipBuriedTets = skipBuried;
    s.fixedTets.resize(mesh.tets.size());
    for (int t = 0; t < int(mesh.tets.size()); ++t) s.fixedTets[t] = t;
    LatticeBody& block = plugin.addLatticeBody(mesh, s, btTransform::getIdentity());
    const GroupShape& group = *collisionGroup(block.pieces()[0]);
    int buried = 0;
    for (int i = 0; i < group.primitiveCount(); ++i) buried += group.buried(i);
    EXPECT_EQ(buried, skipBuried ? 4 * 2 * 4 * 6 : 0); // the tets of the cells with no corner outside
    btBoxShape boxShape(btVector3(0.125f, 0.125f, 0.125f));
    btVector3 inertia;
    boxShape.calculateLocalInertia(2, inertia);
    btRigidBody box(2, nullptr, &boxShape, inertia);
    box.setWorldTransform(btTransform(btQuaternion::getIdentity(), btVector3(0.02f, 0.35f, -0.01f)));
    w.world.addRigidBody(&box);
    w.step(240);
    const btVector3 at = box.getWorldTransform().getOrigin();
    EXPECT_LT(box.getLinearVelocity().length(), 1e-3f);
    w.world.removeRigidBody(&box);
    return at;
}

TEST(BuriedTets, ABoxRestsOnABlockWhereItRestsWithEveryTetInTheContacts) {
    const btVector3 skipping = restingBoxOnBlock(true);
    const btVector3 all = restingBoxOnBlock(false);
    EXPECT_NEAR(skipping.y(), 0.2 + 0.125, 2e-3); // on the block's top face (margins)
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(skipping[k], all[k], 1e-5) << k;
}

} // namespace
} // namespace shatter
