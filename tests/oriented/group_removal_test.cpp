// ShapeMatchingGroups::removeConnections: the groups after connections broke, edited in place,
// are the groups built from scratch over the connections left, bit for bit.
#include "OrientedFixtures.h"
#include <shatter/plugin/common/InputError.h>

#include <gtest/gtest.h>

namespace shatter::oriented {
namespace {

// Every group's members, its deformation at a random pose and one projection from there (with
// the same warm starts) are the same bits in both.
void expectSameGroups(ShapeMatchingGroups& edited, ShapeMatchingGroups& built, const OrientedParticles& rest) {
    ASSERT_EQ(edited.size(), built.size());
    std::mt19937 rng(11);
    OrientedParticles p = rest;
    for (int i = 0; i < p.size(); ++i) {
        p.position[i] += test::randomVector(rng, 0.02);
        p.orientation[i] = (Eigen::Quaterniond(Eigen::AngleAxisd(0.2, test::randomVector(rng, 1.0).normalized())) *
                            p.orientation[i]).normalized();
    }
    for (int g = 0; g < edited.size(); ++g) {
        const auto a = edited.members(g), b = built.members(g);
        ASSERT_EQ(std::vector<int>(a.begin(), a.end()), std::vector<int>(b.begin(), b.end())) << "group " << g;
        const Eigen::Matrix3d Da = edited.deformation(g, p, p.position, p.orientation);
        const Eigen::Matrix3d Db = built.deformation(g, p, p.position, p.orientation);
        EXPECT_TRUE((Da.array() == Db.array()).all()) << "group " << g;
        edited.setRotation(g, Eigen::Quaterniond::Identity());
        built.setRotation(g, Eigen::Quaterniond::Identity());
    }
    OrientedParticles pa = p, pb = p;
    edited.refreshMoments(pa, pa.orientation);
    built.refreshMoments(pb, pb.orientation);
    for (int g = 0; g < edited.size(); ++g) {
        edited.project(g, pa, pa.position, pa.orientation, 0.5, 20);
        built.project(g, pb, pb.position, pb.orientation, 0.5, 20);
    }
    for (int i = 0; i < p.size(); ++i) {
        EXPECT_EQ(pa.position[i], pb.position[i]) << "particle " << i;
        EXPECT_TRUE(pa.orientation[i].coeffs() == pb.orientation[i].coeffs()) << "particle " << i;
    }
}

TEST(GroupRemoval, RemovingConnectionsGivesTheGroupsOfTheConnectionsLeft) {
    const test::CubeBlock block = test::cubeBlock(5, 4, 2, 0.1);
    const OrientedParticles particles = particlesFromPrimitives(block.primitives, 700.0, "block");
    ShapeMatchingGroups edited(particles, block.connections);
    std::vector<std::pair<int, int>> left = block.connections;
    std::mt19937 rng(3);
    // Three rounds of removals (a third of the connections each), given in either order.
    for (int round = 0; round < 3; ++round) {
        std::vector<std::pair<int, int>> gone, kept;
        for (const auto& [a, b] : left) {
            if (rng() % 3 == 0) gone.push_back(rng() % 2 ? std::pair(a, b) : std::pair(b, a));
            else kept.emplace_back(a, b);
        }
        ASSERT_FALSE(gone.empty());
        edited.removeConnections(particles, gone);
        left = kept;
        ShapeMatchingGroups built(particles, left);
        expectSameGroups(edited, built, particles);
    }
}

TEST(GroupRemoval, OtherGroupsKeepTheirRotations) {
    const test::CubeBlock block = test::cubeBlock(4, 4, 1, 0.1);
    const OrientedParticles particles = particlesFromPrimitives(block.primitives, 700.0, "block");
    ShapeMatchingGroups groups(particles, block.connections);
    for (int g = 0; g < groups.size(); ++g)
        groups.setRotation(g, Eigen::Quaterniond(Eigen::AngleAxisd(0.01 * g, Eigen::Vector3d::UnitZ())));
    const std::pair<int, int> gone = block.connections.front();
    groups.removeConnections(particles, std::vector{gone});
    for (int g = 0; g < groups.size(); ++g)
        EXPECT_TRUE(groups.rotation(g).coeffs() ==
                    Eigen::Quaterniond(Eigen::AngleAxisd(0.01 * g, Eigen::Vector3d::UnitZ())).coeffs());
    EXPECT_FALSE(groups.connected(gone.first, gone.second));
    EXPECT_FALSE(groups.connected(gone.second, gone.first));
}

TEST(GroupRemoval, APairThatIsNoConnectionIsAnError) {
    const test::CubeBlock block = test::cubeBlock(3, 1, 1, 0.1); // 0-1, 1-2 connected; 0-2 not
    const OrientedParticles particles = particlesFromPrimitives(block.primitives, 700.0, "block");
    ShapeMatchingGroups groups(particles, block.connections);
    EXPECT_THROW(groups.removeConnections(particles, std::vector{std::pair(0, 2)}), InputError);
    EXPECT_THROW(groups.removeConnections(particles, std::vector{std::pair(0, 7)}), InputError);
    // Nothing changed by the refused calls.
    ShapeMatchingGroups built(particles, block.connections);
    expectSameGroups(groups, built, particles);
}

TEST(GroupRemoval, RebuiltGroupsAreTheGroupsBuiltFromTheSameArguments) {
    // rebuild (a torn body's kept part, in the old groups' memory) over fewer particles and
    // other connections: the constructor's groups, identity warm starts, a new version.
    const test::CubeBlock big = test::cubeBlock(5, 4, 2, 0.1);
    ShapeMatchingGroups rebuilt(particlesFromPrimitives(big.primitives, 700.0, "block"), big.connections);
    for (int g = 0; g < rebuilt.size(); ++g)
        rebuilt.setRotation(g, Eigen::Quaterniond(Eigen::AngleAxisd(0.01 * g, Eigen::Vector3d::UnitZ())));
    const auto before = rebuilt.connectionsVersion();
    const test::CubeBlock part = test::cubeBlock(3, 3, 1, 0.1, Eigen::Vector3d(0.1, 0.2, 0));
    const OrientedParticles particles = particlesFromPrimitives(part.primitives, 800.0, "part");
    std::vector<std::pair<int, int>> connections(part.connections.begin() + 3, part.connections.end());
    rebuilt.rebuild(particles, connections);
    ShapeMatchingGroups built(particles, connections);
    EXPECT_NE(rebuilt.connectionsVersion(), before);
    EXPECT_NE(rebuilt.connectionsVersion(), built.connectionsVersion());
    for (int g = 0; g < rebuilt.size(); ++g)
        EXPECT_TRUE(rebuilt.rotation(g).coeffs() == Eigen::Quaterniond::Identity().coeffs()) << "group " << g;
    expectSameGroups(rebuilt, built, particles);
    // A bad pair is an error, and the groups stay as they were.
    const auto version = rebuilt.connectionsVersion();
    EXPECT_THROW(rebuilt.rebuild(particles, {{0, 9}}), InputError);
    EXPECT_EQ(rebuilt.connectionsVersion(), version);
    ShapeMatchingGroups again(particles, connections);
    expectSameGroups(rebuilt, again, particles);
}

} // namespace
} // namespace shatter::oriented
