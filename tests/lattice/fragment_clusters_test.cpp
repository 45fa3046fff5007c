// The minimum fragment size (FragmentClusters.h): loose parts smaller than it are clustered with
// their loose neighbours or stay attached; the parts still partition the piece, mass and momenta
// are conserved, the clusters hold together, and the result is the same bit for bit.
#include "LatticeFixtures.h"
#include <shatter/plugin/geometry/RigidState.h>
#include <shatter/plugin/lattice/FragmentClusters.h>
#include <shatter/plugin/lattice/Fragments.h>
#include <shatter/plugin/lattice/TetGenerators.h>

#include <gtest/gtest.h>

#include <cmath>

namespace shatter::lattice {
namespace {

// A 0.3 m cube of 3 cm cells (a lone tet is 5-7 cm across), jittered, fixed by its face x = -0.15
// when `anchored`; every link with its face centre at x > 0.05 broken: the tets there all came
// loose one by one, as around a crater on a fine mesh.
Lattice crater(bool anchored) {
    GeneratorOptions o;
    o.jitter = 0.15;
    o.seed = 5;
    Lattice lattice(tetBox({0.3, 0.3, 0.3}, {10, 10, 10}, o), adobe());
    if (anchored)
        for (int t : tetsWithFaceOnPlane(lattice.mesh(), {1, 0, 0}, -0.15, 1e-9)) lattice.setFixed(t, true);
    for (int k = 0; k < lattice.linkCount(); ++k)
        if (lattice.links()[k].faceCentre.x() > 0.05) lattice.breakLink(k);
    return lattice;
}

double sizeOf(const Lattice& lattice, const std::vector<int>& part) {
    return pieceSize(lattice, part, pieceMassProperties(lattice, part).centerOfMass);
}

bool holdsFixed(const Lattice& lattice, const std::vector<int>& part) {
    return std::any_of(part.begin(), part.end(), [&](int p) { return lattice.particles()[p].fixed; });
}

TEST(FragmentClusters, LooseTetsLeaveInPiecesOfAtLeastTheMinimumSize) {
    constexpr double kMin = 0.12;
    Lattice lattice = crater(true);
    LatticePiece piece = makePiece(lattice, test::indices(lattice.particleCount()));
    const auto singles = connectedComponents(lattice, piece.particles);
    ASSERT_GT(singles.size(), 500u); // the loose tets, one part each (a few pairs), and the anchored rest
    size_t looseTets = 0;
    for (const auto& part : singles) {
        if (holdsFixed(lattice, part)) continue;
        ASSERT_LT(sizeOf(lattice, part), kMin);
        looseTets += part.size();
    }
    const int brokenBefore = lattice.brokenCount();
    const auto parts = fragmentParts(lattice, piece, kMin);
    // Every loose tet had loose neighbours, so all of them leave, in clusters of the minimum size.
    size_t left = 0;
    int anchoredParts = 0;
    for (const auto& part : parts) {
        if (holdsFixed(lattice, part)) {
            ++anchoredParts;
            continue;
        }
        EXPECT_GE(sizeOf(lattice, part), kMin);
        left += part.size();
    }
    EXPECT_EQ(anchoredParts, 1);
    EXPECT_EQ(left, looseTets);
    EXPECT_GT(parts.size(), 2u);
    EXPECT_LT(parts.size(), singles.size() / 10);
    // Each cluster holds together by its joined links, which nothing can break.
    int joined = 0;
    for (const auto& part : parts) EXPECT_EQ(connectedComponents(lattice, part).size(), 1u);
    for (const Link& l : lattice.links())
        if (!l.broken && std::isinf(l.strength)) {
            EXPECT_TRUE(std::isinf(l.baseStrength));
            ++joined;
        }
    EXPECT_EQ(lattice.brokenCount(), brokenBefore - joined);
    EXPECT_GT(joined, 0);
}

TEST(FragmentClusters, PartsPartitionThePieceAndConserveMassAndMomenta) {
    Lattice lattice = crater(false);
    LatticePiece piece = makePiece(lattice, test::indices(lattice.particleCount()));
    const auto parts = fragmentParts(lattice, piece, 0.1);
    ASSERT_GT(parts.size(), 2u);
    std::vector<int> seen;
    for (const auto& part : parts) {
        EXPECT_TRUE(std::is_sorted(part.begin(), part.end()));
        seen.insert(seen.end(), part.begin(), part.end());
    }
    std::sort(seen.begin(), seen.end());
    EXPECT_EQ(seen, test::indices(lattice.particleCount()));
    for (size_t i = 1; i < parts.size(); ++i) EXPECT_LT(parts[i - 1][0], parts[i][0]);
    // The whole body moving and spinning: its parts take their motion from it (partState).
    const auto whole = pieceMassProperties(lattice, test::indices(lattice.particleCount()));
    geometry::RigidState parent;
    parent.mass = whole.mass;
    parent.centre = whole.centerOfMass;
    parent.inertia = whole.inertia;
    parent.velocity = Eigen::Vector3d(4.0, -2.5, 1.0);
    parent.angularVelocity = Eigen::Vector3d(-3.0, 7.0, 2.0);
    double mass = 0;
    Eigen::Vector3d p = Eigen::Vector3d::Zero(), l = Eigen::Vector3d::Zero();
    for (const auto& part : parts) {
        const geometry::RigidState s = geometry::partState(parent, pieceMassProperties(lattice, part));
        mass += s.mass;
        p += s.linearMomentum();
        l += s.angularMomentum();
    }
    EXPECT_NEAR(mass, parent.mass, 1e-12 * parent.mass);
    EXPECT_LT((p - parent.linearMomentum()).norm(), 1e-9 * parent.linearMomentum().norm());
    EXPECT_LT((l - parent.angularMomentum()).norm(), 1e-9 * parent.angularMomentum().norm());
}

TEST(FragmentClusters, ALoneTetBelowTheSizeStaysAttachedAndItsLinksAreSolvedAgain) {
    Lattice lattice(tetBox({0.3, 0.3, 0.3}, {6, 6, 6}), adobe());
    for (int t : tetsWithFaceOnPlane(lattice.mesh(), {0, 1, 0}, -0.15, 1e-9)) lattice.setFixed(t, true);
    LatticePiece piece = makePiece(lattice, test::indices(lattice.particleCount()));
    const int rows = piece.constraintSystem(lattice).rowCount();
    const int middle = lattice.particleCount() / 2;
    const int brokenLinks = int(lattice.linksOf(middle).size());
    for (int k : lattice.linksOf(middle)) lattice.breakLink(k);
    piece.rebuild(lattice); // as the fracture analysis leaves it
    ASSERT_EQ(piece.system->rowCount(), rows - brokenLinks);
    ASSERT_EQ(connectedComponents(lattice, piece.particles).size(), 2u);
    const auto parts = fragmentParts(lattice, piece, 0.2);
    ASSERT_EQ(parts.size(), 1u); // no split
    EXPECT_EQ(parts[0], piece.particles);
    EXPECT_EQ(lattice.brokenCount(), 0);
    EXPECT_EQ(piece.system->rowCount(), rows); // the joined links are in the system again
    EXPECT_EQ(piece.lambda.size(), rows);
    // Without a minimum the tet comes loose (its joined links broken here by hand).
    for (int k : lattice.linksOf(middle)) lattice.breakLink(k);
    EXPECT_EQ(fragmentParts(lattice, piece, 0.0).size(), 2u);
}

TEST(FragmentClusters, APieceBelowTheSizeDoesNotSplit) {
    Lattice lattice(tetBox({0.04, 0.04, 0.04}, {2, 2, 2}), glass());
    for (int k = 0; k < lattice.linkCount(); ++k) lattice.breakLink(k);
    LatticePiece piece = makePiece(lattice, test::indices(lattice.particleCount()));
    EXPECT_EQ(fragmentParts(lattice, piece, 0.1).size(), 1u);
    EXPECT_EQ(lattice.brokenCount(), 0);
}

TEST(FragmentClusters, WithoutAMinimumThePartsAreTheConnectedComponents) {
    Lattice lattice = crater(true);
    const auto components = connectedComponents(lattice, test::indices(lattice.particleCount()));
    LatticePiece piece = makePiece(lattice, test::indices(lattice.particleCount()));
    const int broken = lattice.brokenCount();
    EXPECT_EQ(fragmentParts(lattice, piece, 0.0), components);
    EXPECT_EQ(fragmentParts(lattice, piece, 0.01), components); // every tet is larger than 1 cm
    EXPECT_EQ(lattice.brokenCount(), broken);
}

TEST(FragmentClusters, SameInputGivesTheSameClustersAndLinksBitForBit) {
    auto run = [] {
        Lattice lattice = crater(true);
        LatticePiece piece = makePiece(lattice, test::indices(lattice.particleCount()));
        auto parts = fragmentParts(lattice, piece, 0.09);
        std::vector<char> broken;
        for (const Link& l : lattice.links()) broken.push_back(l.broken);
        return std::make_pair(parts, broken);
    };
    const auto a = run(), b = run();
    EXPECT_EQ(a.first, b.first);
    EXPECT_EQ(a.second, b.second);
    EXPECT_GT(a.first.size(), 2u);
}

} // namespace
} // namespace shatter::lattice
