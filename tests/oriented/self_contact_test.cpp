// Self-contact candidates of an oriented-particle body (SelfContacts.h).
#include "OrientedFixtures.h"
#include <shatter/plugin/oriented/SelfContacts.h>

#include <gtest/gtest.h>

#include <limits>
#include <set>

namespace shatter::oriented {
namespace {

TEST(SelfContacts, TreeWalkFindsExactlyTheUnconnectedPairsWhoseBoxesOverlap) {
    // A 6 × 4 × 3 block jumbled by turns and shifts of half a cell: the walk over a tree of
    // the moved boxes gives the same pairs as checking every pair, each measured by
    // faceSeparation.
    std::mt19937 rng(21);
    const auto block = test::cubeBlock(6, 4, 3, 0.1);
    const auto solver = test::blockSolver(block);
    auto moved = block.primitives;
    for (size_t i = 0; i < moved.size(); ++i) {
        Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
        const Eigen::Vector3d axis = test::randomVector(rng, 1).normalized();
        pose.linear() = Eigen::AngleAxisd(0.5, axis).toRotationMatrix();
        const Eigen::Vector3d centre = block.primitives[i].massProperties(1.0).centerOfMass;
        pose.translation() = centre - pose.linear() * centre + test::randomVector(rng, 0.05);
        moved[i].moveTo(block.primitives[i], pose);
    }
    const double reach = std::numeric_limits<double>::infinity(); // every overlapping pair is a contact
    std::vector<geometry::Aabb> boxes;
    for (const auto& p : moved) boxes.push_back(p.bounds());
    std::vector<ParticleContact> contacts;
    addSelfContacts(moved, geometry::AabbTree(boxes), solver.groups(), reach, 0.3, contacts);

    std::set<std::pair<int, int>> expected;
    for (int a = 0; a < int(moved.size()); ++a)
        for (int b = a + 1; b < int(moved.size()); ++b)
            if (moved[size_t(a)].bounds().overlaps(moved[size_t(b)].bounds()) && !solver.groups().connected(a, b))
                expected.insert({a, b});
    ASSERT_GT(expected.size(), 20u); // the jumble makes unconnected overlaps
    std::set<std::pair<int, int>> found;
    for (const ParticleContact& c : contacts) {
        EXPECT_TRUE(found.insert({c.particle, c.otherParticle}).second) << "pair found twice";
        const PrimitiveSeparation s = faceSeparation(moved[size_t(c.particle)], moved[size_t(c.otherParticle)]);
        EXPECT_EQ(c.distance, s.distance);
        EXPECT_EQ(c.normal, s.normal);
        EXPECT_EQ(c.friction, 0.3);
    }
    EXPECT_EQ(found, expected);
}

} // namespace
} // namespace shatter::oriented
