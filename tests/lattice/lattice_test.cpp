// The lattice built from a tet mesh (source 002 §2): particles, links, strengths, materials.
#include "LatticeFixtures.h"
#include <shatter/plugin/common/InputError.h>
#include <shatter/plugin/lattice/Lattice.h>
#include <shatter/plugin/lattice/TetGenerators.h>

#include <gtest/gtest.h>

namespace shatter::lattice {
namespace {

TEST(Lattice, ParticlesAtCentroidsWithVolumeTimesDensity) {
    GeneratorOptions o;
    o.jitter = 0.15;
    const Lattice lattice(tetBox({1.0, 0.6, 0.4}, {5, 3, 2}, o), adobe());
    ASSERT_EQ(lattice.particleCount(), 180);
    double mass = 0.0;
    for (int i = 0; i < lattice.particleCount(); ++i) {
        const Particle& p = lattice.particles()[i];
        const Tet& t = lattice.mesh().tets[i];
        EXPECT_TRUE(p.position.isApprox(centroid(lattice.mesh(), t), 1e-15));
        EXPECT_DOUBLE_EQ(p.mass, signedVolume(lattice.mesh(), t) * 1700.0);
        mass += p.mass;
    }
    EXPECT_NEAR(lattice.totalMass(), 0.24 * 1700.0, 1e-9);
    EXPECT_DOUBLE_EQ(mass, lattice.totalMass());
}

TEST(Lattice, OneLinkPerSharedFaceWithAreaTimesStrength) {
    const Lattice lattice(tetBox({1.0, 1.0, 1.0}, {2, 2, 2}), glass());
    EXPECT_EQ(lattice.linkCount(), int(lattice.faces().shared.size()));
    for (const Link& l : lattice.links()) {
        const Eigen::Vector3d d = lattice.particles()[l.a].position - lattice.particles()[l.b].position;
        EXPECT_NEAR(l.length, d.norm(), 1e-15);
        EXPECT_TRUE(l.normal.isApprox(d.normalized(), 1e-14));
        // Kuhn faces are right triangles with legs of one cell (0.5 m) or a cell and a face
        // diagonal: area 0.125 or 0.125·√2 m².
        EXPECT_TRUE(std::abs(l.area - 0.125) < 1e-12 || std::abs(l.area - 0.125 * std::sqrt(2.0)) < 1e-12) << l.area;
        EXPECT_DOUBLE_EQ(l.strength, l.area * glass().strength);
        EXPECT_EQ(l.strength, l.baseStrength);
        EXPECT_LT(l.a, l.b);
    }
    // Each particle lists exactly its links.
    int listed = 0;
    for (int i = 0; i < lattice.particleCount(); ++i)
        for (int k : lattice.linksOf(i)) {
            EXPECT_TRUE(lattice.links()[k].a == i || lattice.links()[k].b == i);
            ++listed;
        }
    EXPECT_EQ(listed, 2 * lattice.linkCount());
}

TEST(Lattice, IsBrokenFollowsBreakingAndJoiningLikeTheLinks) {
    Lattice lattice(tetBox({1.0, 1.0, 1.0}, {2, 2, 2}), glass());
    auto agrees = [&] {
        for (int k = 0; k < lattice.linkCount(); ++k)
            if (lattice.isBroken(k) != lattice.links()[k].broken) return false;
        return true;
    };
    EXPECT_TRUE(agrees());
    lattice.breakLink(3);
    lattice.breakLink(7);
    lattice.breakLink(3); // again: no change
    EXPECT_TRUE(lattice.isBroken(3) && lattice.isBroken(7));
    EXPECT_TRUE(agrees());
    EXPECT_EQ(lattice.brokenCount(), 2);
    lattice.joinLink(7);
    EXPECT_FALSE(lattice.isBroken(7));
    EXPECT_TRUE(lattice.isBroken(3));
    EXPECT_TRUE(agrees());
}

TEST(Lattice, MaterialsHaveDocumentedDefaultsAndBadOnesAreErrors) {
    for (const auto& name : materialNames()) {
        const MaterialSettings m = materialNamed(name);
        EXPECT_EQ(m.name, name);
        EXPECT_NO_THROW(m.check("body"));
    }
    EXPECT_EQ(MaterialSettings().name, "adobe");
    EXPECT_THROW(materialNamed("cheese"), InputError);
    MaterialSettings bad = glass();
    bad.density = 0.0;
    EXPECT_THROW(Lattice(tetBox({1, 1, 1}, {1, 1, 1}), bad), InputError);
    bad = glass();
    bad.strength = -1.0;
    try {
        Lattice(tetBox({1, 1, 1}, {1, 1, 1}), bad);
        FAIL();
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("strength must be positive"), std::string::npos) << e.what();
    }
}

TEST(Lattice, FixedTetsOnTheGroundPlane) {
    const TetMesh wall = tetBox({2.0, 1.0, 0.5}, {4, 2, 1});
    const std::vector<int> bottom = tetsWithFaceOnPlane(wall, {0, 1, 0}, -0.5, 1e-9);
    // Each bottom cell has two tets with a face on its bottom square.
    EXPECT_EQ(bottom.size(), size_t(4 * 1 * 2));
    for (int t : bottom) EXPECT_LT(centroid(wall, wall.tets[t]).y(), -0.25);
    Lattice lattice(wall, adobe());
    lattice.setFixed(bottom[0], true);
    EXPECT_EQ(lattice.inverseMass(bottom[0]), 0.0);
    EXPECT_GT(lattice.inverseMass(bottom[1]), 0.0);
}

TEST(Lattice, ChainFixtureIsAVerticalLineOfLinks) {
    const Lattice chain(test::verticalChain(8), adobe());
    EXPECT_EQ(chain.linkCount(), 7);
    for (const Link& l : chain.links()) EXPECT_NEAR(std::abs(l.normal.y()), 1.0, 1e-15);
    const Lattice star(test::starOfFive(), adobe());
    EXPECT_EQ(star.linkCount(), 4);
}

} // namespace
} // namespace shatter::lattice
