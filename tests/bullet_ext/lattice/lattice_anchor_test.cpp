// Anchoring a lattice body where it is placed (issue 19): by regions in world coordinates and
// by contact with static Bullet bodies, united with an explicit list; an anchor that holds no
// tet is an error naming the body.
#include <shatter/bullet_ext/Plugin.h>
#include <shatter/bullet_ext/VisualBody.h>
#include <shatter/bullet_ext/lattice/LatticeAnchors.h>
#include <shatter/bullet_ext/lattice/LatticeBody.h>
#include <shatter/plugin/common/InputError.h>
#include <shatter/plugin/lattice/AnchorRegion.h>
#include <shatter/plugin/lattice/TetGenerators.h>
#include "tests/support/TestWorld.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <string>

namespace shatter {
namespace {

// A 0.4 m cube of 4 × 4 × 4 cells (384 tets), centred on its mesh origin.
lattice::TetMesh cube() { return lattice::tetBox({0.4, 0.4, 0.4}, {4, 4, 4}); }

// The tets with a node on the plane y = `y` (mesh coordinates).
std::vector<int> tetsWithNodeAt(const lattice::TetMesh& mesh, double y) {
    std::vector<int> out;
    for (int t = 0; t < int(mesh.tets.size()); ++t)
        if (std::any_of(mesh.tets[t].begin(), mesh.tets[t].end(), [&](int n) { return std::abs(mesh.nodes[n].y() - y) < 1e-9; }))
            out.push_back(t);
    return out;
}

std::string errorOf(const std::function<void()>& f) {
    try {
        f();
    } catch (const InputError& e) {
        return e.what();
    }
    return "no error";
}

TEST(LatticeAnchors, TheTetsTouchingTheGroundAreAnchoredAndTheBodyStands) {
    test::TestWorld w;
    w.addGround();
    Plugin plugin(w.world);
    const lattice::TetMesh mesh = cube();
    LatticeSettings s;
    s.name = "block";
    s.anchorTo = {w.ground.get()};
    // Resting on the ground (y = 0): every tet with a corner on it touches, no other does
    // (the next nodes are 0.1 m up).
    const btTransform pose(btQuaternion::getIdentity(), btVector3(0, 0.2f, 0));
    LatticeBody& body = plugin.addLatticeBody(mesh, s, pose);
    const std::vector<int> expected = tetsWithNodeAt(mesh, -0.2);
    EXPECT_EQ(body.settings().fixedTets, expected);
    EXPECT_GT(expected.size(), lattice::tetsWithFaceOnPlane(mesh, {0, 1, 0}, -0.2, 1e-9).size());
    ASSERT_EQ(body.pieceCount(), 1);
    EXPECT_EQ(body.pieces()[0].body->rigidBody().getInvMass(), 0) << "an anchored body is static";
    w.step(60);
    EXPECT_EQ(body.pieceCount(), 1);
}

TEST(LatticeAnchors, ContactWithABoxAnchorsTheTetsOnIt) {
    // The cube's corner rests on a static 0.1 m post under x, z in [0.1, 0.2]: the tets with a
    // corner on the post's top, and within 1 mm of it, are anchored; none elsewhere.
    test::TestWorld w;
    Plugin plugin(w.world);
    btBoxShape postShape(btVector3(0.05f, 0.5f, 0.05f));
    postShape.setMargin(0.0005f); // Bullet rounds a box's edges by its margin (4 cm by default)
    btRigidBody post(0, nullptr, &postShape);
    post.setWorldTransform(btTransform(btQuaternion::getIdentity(), btVector3(0.15f, -0.5f, 0.15f)));
    w.world.addRigidBody(&post);
    const lattice::TetMesh mesh = cube();
    LatticeSettings s;
    s.name = "block";
    s.anchorTo = {&post};
    const btTransform pose(btQuaternion::getIdentity(), btVector3(0, 0.2f, 0));
    LatticeBody& body = plugin.addLatticeBody(mesh, s, pose);
    const auto& fixed = body.settings().fixedTets;
    ASSERT_FALSE(fixed.empty());
    for (int t : fixed) {
        const auto& tet = mesh.tets[t];
        const bool onPost = std::any_of(tet.begin(), tet.end(), [&](int n) {
            const Eigen::Vector3d& p = mesh.nodes[n];
            return std::abs(p.y() + 0.2) < 1e-9 && p.x() >= 0.1 - 1e-9 && p.z() >= 0.1 - 1e-9;
        });
        EXPECT_TRUE(onPost) << "tet " << t << " does not touch the post";
    }
    // The post's top (one cell) holds the corner cell's six tets, which share its corner node.
    EXPECT_GE(fixed.size(), 6u);
    w.world.removeRigidBody(&post);
}

TEST(LatticeAnchors, WorldRegionsAndTheListAreUnited) {
    test::TestWorld w;
    Plugin plugin(w.world);
    const lattice::TetMesh mesh = cube();
    LatticeSettings s;
    s.name = "block";
    // Placed 2 m up: world y <= 1.9 is the mesh's lowest cell layer (centroids below -0.1).
    s.anchorRegions = {lattice::AnchorRegion::below(1.9).inWorld()};
    s.fixedTets = {383};
    LatticeBody& body = plugin.addLatticeBody(mesh, s, btTransform(btQuaternion::getIdentity(), btVector3(0, 2, 0)));
    std::vector<int> expected = lattice::tetsInRegion(mesh, lattice::AnchorRegion::below(-0.1));
    EXPECT_EQ(expected.size(), mesh.tets.size() / 4);
    expected.push_back(383);
    EXPECT_EQ(body.settings().fixedTets, expected);
    EXPECT_TRUE(body.settings().anchorRegions.empty());
}

TEST(LatticeAnchors, AnAnchorThatHoldsNothingIsAnErrorNamingTheBody) {
    test::TestWorld w;
    w.addGround();
    Plugin plugin(w.world);
    const lattice::TetMesh mesh = cube();
    const btTransform high(btQuaternion::getIdentity(), btVector3(0, 1, 0)); // 0.8 m above the ground
    LatticeSettings s;
    s.name = "statue";
    s.anchorTo = {w.ground.get()};
    EXPECT_NE(errorOf([&] { plugin.addLatticeBody(mesh, s, high); }).find("body 'statue': anchor body 0 touches no tet"),
              std::string::npos);
    s.anchorTo = {nullptr};
    EXPECT_NE(errorOf([&] { plugin.addLatticeBody(mesh, s, high); }).find("body 'statue': anchor body 0 is null"), std::string::npos);
    btSphereShape ballShape(0.1f);
    btRigidBody ball(1, nullptr, &ballShape, btVector3(0.004f, 0.004f, 0.004f));
    s.anchorTo = {&ball};
    EXPECT_NE(errorOf([&] { plugin.addLatticeBody(mesh, s, high); }).find("body 'statue': anchor body 0 is not static"),
              std::string::npos);
    s.anchorTo.clear();
    s.anchorRegions = {lattice::AnchorRegion::below(0.5).inWorld()};
    EXPECT_NE(errorOf([&] { plugin.addLatticeBody(mesh, s, high); })
                  .find("body 'statue': the anchor region n·x <= 0.5 with n = (0, 1, 0) (world coordinates) holds no tet"),
              std::string::npos);
    EXPECT_TRUE(plugin.bodies().empty()) << "a failed body leaves nothing behind";
}

} // namespace
} // namespace shatter
