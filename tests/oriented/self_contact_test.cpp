// Self-contact candidates of an oriented-particle body (SelfContacts.h).
#include "OrientedFixtures.h"
#include <shatter/plugin/oriented/SelfContacts.h>

#include <gtest/gtest.h>

#include <limits>
#include <set>

namespace shatter::oriented {
namespace {

using Pairs = std::set<std::pair<int, int>>;

// Every pair of unconnected primitives whose boxes overlap, by checking every pair.
Pairs overlappingUnconnected(const std::vector<geometry::ConvexPolyhedron>& moved, const ShapeMatchingGroups& groups) {
    Pairs pairs;
    for (int a = 0; a < int(moved.size()); ++a)
        for (int b = a + 1; b < int(moved.size()); ++b)
            if (moved[size_t(a)].bounds().overlaps(moved[size_t(b)].bounds()) && !groups.connected(a, b))
                pairs.insert({a, b});
    return pairs;
}

// A tree over the primitives' boxes.
geometry::AabbTree treeOver(const std::vector<geometry::ConvexPolyhedron>& primitives) {
    std::vector<geometry::Aabb> boxes;
    for (const auto& p : primitives) boxes.push_back(p.bounds());
    return geometry::AabbTree(boxes);
}

// The pairs of `contacts`, checking that each comes once, particle < otherParticle, measured
// by faceSeparation.
Pairs contactPairs(const std::vector<ParticleContact>& contacts, const std::vector<geometry::ConvexPolyhedron>& moved) {
    Pairs found;
    for (const ParticleContact& c : contacts) {
        EXPECT_LT(c.particle, c.otherParticle);
        EXPECT_TRUE(found.insert({c.particle, c.otherParticle}).second) << "pair found twice";
        const PrimitiveSeparation s = faceSeparation(moved[size_t(c.particle)], moved[size_t(c.otherParticle)]);
        EXPECT_EQ(c.distance, s.distance);
        EXPECT_EQ(c.normal, s.normal);
        EXPECT_EQ(c.friction, 0.3);
    }
    return found;
}

// Primitive i of `block` turned by `angle` about a random axis through its centre and shifted
// by up to `shift` on each axis.
void jumble(const test::CubeBlock& block, std::vector<geometry::ConvexPolyhedron>& moved, std::mt19937& rng,
            double angle, double shift) {
    for (size_t i = 0; i < moved.size(); ++i) {
        Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
        const Eigen::Vector3d axis = test::randomVector(rng, 1).normalized();
        pose.linear() = Eigen::AngleAxisd(angle, axis).toRotationMatrix();
        const Eigen::Vector3d centre = block.primitives[i].massProperties(1.0).centerOfMass;
        pose.translation() = centre - pose.linear() * centre + test::randomVector(rng, shift);
        moved[i].moveTo(block.primitives[i], pose);
    }
}

TEST(SelfContacts, CandidatesFindExactlyTheUnconnectedPairsWhoseBoxesOverlap) {
    // A 6 × 4 × 3 block jumbled by turns and shifts of half a cell: the candidate list (over
    // a tree of the moved boxes) gives the same pairs as checking every pair.
    std::mt19937 rng(21);
    const auto block = test::cubeBlock(6, 4, 3, 0.1);
    const auto solver = test::blockSolver(block);
    auto moved = block.primitives;
    jumble(block, moved, rng, 0.5, 0.05);
    const double reach = std::numeric_limits<double>::infinity(); // every overlapping pair is a contact
    std::vector<ParticleContact> contacts;
    SelfContactCandidates(0.01).addContacts(moved, treeOver(moved), solver.groups(), reach, 0.3, contacts);
    const Pairs expected = overlappingUnconnected(moved, solver.groups());
    ASSERT_GT(expected.size(), 20u); // the jumble makes unconnected overlaps
    EXPECT_EQ(contactPairs(contacts, moved), expected);
}

TEST(SelfContacts, AListOutlivesAMoveOfTheWholeBodyButNotOneOfAPart) {
    // A jumbled block carried along as a whole (20 skins a call, plus a jiggle of a tenth of a
    // skin per primitive) keeps its first list: every box moved back by the common shift is
    // still inside its grown box, and overlaps do not change under a common shift. The pairs
    // are still exactly the overlapping unconnected ones. One primitive alone moved by three
    // skins then makes the list again.
    std::mt19937 rng(8);
    const auto block = test::cubeBlock(6, 4, 3, 0.1);
    const auto solver = test::blockSolver(block);
    auto jumbled = block.primitives;
    jumble(block, jumbled, rng, 0.5, 0.05);
    const geometry::AabbTree tree = treeOver(jumbled);
    const double skin = 0.01, reach = std::numeric_limits<double>::infinity();
    SelfContactCandidates candidates(skin);
    auto moved = jumbled;
    for (int call = 0; call < 12; ++call) {
        const Eigen::Vector3d carried = Eigen::Vector3d(0.2, -0.3, 0.1) * call;
        for (size_t i = 0; i < moved.size(); ++i) {
            Eigen::Isometry3d shift = Eigen::Isometry3d::Identity();
            shift.translation() = carried + test::randomVector(rng, 0.1 * skin);
            moved[i] = jumbled[i].transformed(shift);
        }
        std::vector<ParticleContact> contacts;
        candidates.addContacts(moved, tree, solver.groups(), reach, 0.3, contacts);
        const Pairs expected = overlappingUnconnected(moved, solver.groups());
        ASSERT_GT(expected.size(), 20u);
        EXPECT_EQ(contactPairs(contacts, moved), expected) << "call " << call;
    }
    EXPECT_EQ(candidates.rebuilds(), 1);
    Eigen::Isometry3d alone = Eigen::Isometry3d::Identity();
    alone.translation() = Eigen::Vector3d(3.0 * skin, 0.0, 0.0);
    moved[7] = moved[7].transformed(alone);
    std::vector<ParticleContact> contacts;
    candidates.addContacts(moved, tree, solver.groups(), reach, 0.3, contacts);
    EXPECT_EQ(candidates.rebuilds(), 2);
    EXPECT_EQ(contactPairs(contacts, moved), overlappingUnconnected(moved, solver.groups()));
}

TEST(SelfContacts, KeptCandidatesStayExactAsPrimitivesMoveAndConnectionsAreCut) {
    // The block is squashed towards its middle a little more at each call (to 55% of its
    // size), its cubes turning a little further each time: a list kept between calls gives,
    // every call, the pairs checking every pair gives, and is remade only when a cube has left
    // its grown box. The tree is the rest block's, as a body's tree is refitted, not rebuilt.
    // Then, with no move, connections cut (a torn body's new groups) show at once.
    std::mt19937 rng(5);
    const auto block = test::cubeBlock(6, 4, 3, 0.1);
    const auto solver = test::blockSolver(block);
    const Eigen::Vector3d middle(0.3, 0.2, 0.15);
    auto moved = block.primitives;
    const geometry::AabbTree tree = treeOver(block.primitives);
    std::vector<Eigen::Quaterniond> turn(moved.size(), Eigen::Quaterniond::Identity());
    SelfContactCandidates candidates(0.02);
    const double reach = std::numeric_limits<double>::infinity();
    const int calls = 30;
    size_t pairsSeen = 0;
    for (int call = 0; call < calls; ++call) {
        const double squash = 1.0 - 0.015 * call;
        for (size_t i = 0; i < moved.size(); ++i) {
            turn[i] = Eigen::Quaterniond(Eigen::AngleAxisd(0.02, test::randomVector(rng, 1).normalized())) * turn[i];
            const Eigen::Vector3d centre = block.primitives[i].massProperties(1.0).centerOfMass;
            Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
            pose.linear() = turn[i].toRotationMatrix();
            pose.translation() = middle + squash * (centre - middle) - pose.linear() * centre;
            moved[i].moveTo(block.primitives[i], pose);
        }
        std::vector<ParticleContact> contacts;
        candidates.addContacts(moved, tree, solver.groups(), reach, 0.3, contacts);
        const Pairs expected = overlappingUnconnected(moved, solver.groups());
        EXPECT_EQ(contactPairs(contacts, moved), expected) << "call " << call;
        pairsSeen += expected.size();
    }
    EXPECT_GT(pairsSeen, 100u);
    EXPECT_GT(candidates.rebuilds(), 1);
    EXPECT_LT(candidates.rebuilds(), calls);

    // Connections cut in place (a tear that keeps the body whole): the cut pairs that overlap
    // show at once, after one rebuild.
    {
        ShapeMatchingGroups torn = solver.groups();
        const std::vector<std::pair<int, int>> cut{{0, 1}, {1, 2}, {0, 6}};
        torn.removeConnections(solver.particles(), cut);
        const int before = candidates.rebuilds();
        std::vector<ParticleContact> tornContacts;
        candidates.addContacts(moved, tree, torn, reach, 0.3, tornContacts);
        EXPECT_EQ(candidates.rebuilds(), before + 1);
        const Pairs expectedTorn = overlappingUnconnected(moved, torn);
        EXPECT_GT(expectedTorn.size(), overlappingUnconnected(moved, solver.groups()).size());
        EXPECT_EQ(contactPairs(tornContacts, moved), expectedTorn);
    }

    // No connections at all (other groups, as a torn body's): every overlapping pair,
    // neighbours included, after one rebuild.
    const int rebuilds = candidates.rebuilds();
    const OrientedSolver cut("block", particlesFromPrimitives(block.primitives, 1000.0, "block"), {}, {});
    std::vector<ParticleContact> contacts;
    candidates.addContacts(moved, tree, cut.groups(), reach, 0.3, contacts);
    EXPECT_EQ(candidates.rebuilds(), rebuilds + 1);
    EXPECT_EQ(contactPairs(contacts, moved), overlappingUnconnected(moved, cut.groups()));
    EXPECT_GT(contacts.size(), 2 * pairsSeen / calls);
}

} // namespace
} // namespace shatter::oriented
