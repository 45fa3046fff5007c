// The oriented-box test (NearBox.h), two axes at a time, against the 15 axes tried one by one
// in Eigen (the test as it was): the same answer for every pair, and the same least slack at
// which a pair comes within it, to the last bit.
#include <shatter/bullet_ext/shape/NearBox.h>
#include <shatter/plugin/geometry/AabbTree.h>

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <random>
#include <set>
#include <utility>
#include <vector>

namespace shatter {
namespace {

// The 15-axis test one axis at a time, with Eigen's operations.
bool withinOneByOne(const geometry::Aabb& a, const geometry::Aabb& b, const BoxTurn& turn, double slack) {
    const Eigen::Matrix3d &r = turn.r, &absR = turn.absR;
    const Eigen::Vector3d hb = 0.5 * b.extent(), centre = turn.bToA * b.center();
    const Eigen::Vector3d ha = 0.5 * a.extent();
    const Eigen::Vector3d t = centre - a.center();
    for (int i = 0; i < 3; ++i)
        if (std::abs(t[i]) > ha[i] + absR.row(i).dot(hb) + slack) return false;
    for (int j = 0; j < 3; ++j)
        if (std::abs(t.dot(r.col(j))) > absR.col(j).dot(ha) + hb[j] + slack) return false;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            const int i1 = (i + 1) % 3, i2 = (i + 2) % 3;
            const double ra = ha[i1] * absR(i2, j) + ha[i2] * absR(i1, j);
            const double rb = hb[(j + 1) % 3] * absR(i, (j + 2) % 3) + hb[(j + 2) % 3] * absR(i, (j + 1) % 3);
            if (std::abs(t[i2] * r(i1, j) - t[i1] * r(i2, j)) > ra + rb + slack) return false;
        }
    return true;
}

geometry::Aabb randomBox(std::mt19937& rng, double spread) {
    std::uniform_real_distribution<double> u(-1.0, 1.0), size(0.01, 0.2);
    const Eigen::Vector3d c(spread * u(rng), spread * u(rng), spread * u(rng));
    const Eigen::Vector3d h(size(rng), size(rng), size(rng));
    return {c - h, c + h};
}

// Random turns; every fourth a quarter turn about an axis (zero and −0 entries), every
// eighth none.
Eigen::Isometry3d randomTurn(std::mt19937& rng, int trial) {
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
    if (trial % 8 == 0) {
    } else if (trial % 4 == 0) {
        t.linear() = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::Unit(trial / 4 % 3)).toRotationMatrix();
    } else {
        t.linear() = Eigen::AngleAxisd(3.0 * u(rng), Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized()).toRotationMatrix();
    }
    t.translation() = Eigen::Vector3d(0.2 * u(rng), 0.2 * u(rng), 0.2 * u(rng));
    return t;
}

TEST(NearBox, GivesTheOneByOneAnswerForEveryPair) {
    std::mt19937 rng(41);
    int near = 0, far = 0;
    for (int trial = 0; trial < 20000; ++trial) {
        const BoxTurn turn(randomTurn(rng, trial));
        const geometry::Aabb a = randomBox(rng, 0.4), b = randomBox(rng, 0.4);
        const double slack = trial % 3 == 0 ? 0.0 : 0.01 * (trial % 7);
        const bool expected = withinOneByOne(a, b, turn, slack);
        EXPECT_EQ(NearBox(b, turn, slack).within(a), expected) << "trial " << trial;
        (expected ? near : far) += 1;
    }
    EXPECT_GT(near, 2000);
    EXPECT_GT(far, 2000);
}

// The least slack (to the last bit, up to `most`, where `within` must hold) at which `within`
// holds, found by bisection over the doubles.
template <typename Within>
double leastSlack(const Within& within, double most) {
    std::uint64_t low = std::bit_cast<std::uint64_t>(0.0), high = std::bit_cast<std::uint64_t>(most);
    while (high - low > 1) { // positive doubles order as their bits
        const std::uint64_t mid = low + (high - low) / 2;
        (within(std::bit_cast<double>(mid)) ? high : low) = mid;
    }
    return std::bit_cast<double>(high);
}

// At the least slack that brings a pair within (found on the one-by-one test by bisection over
// the doubles), and one double below it, both tests agree: any axis computed with other bits
// would move that edge.
TEST(NearBox, FlipsAtTheSameSlackToTheLastBit) {
    std::mt19937 rng(43);
    for (int trial = 0; trial < 3000; ++trial) {
        const BoxTurn turn(randomTurn(rng, trial));
        const geometry::Aabb a = randomBox(rng, 0.5), b = randomBox(rng, 0.5);
        if (withinOneByOne(a, b, turn, 0.0)) continue;
        ASSERT_TRUE(withinOneByOne(a, b, turn, 4.0));
        const double least = leastSlack([&](double slack) { return withinOneByOne(a, b, turn, slack); }, 4.0);
        const double below = std::bit_cast<double>(std::bit_cast<std::uint64_t>(least) - 1);
        EXPECT_TRUE(NearBox(b, turn, least).within(a)) << "trial " << trial;
        EXPECT_FALSE(NearBox(b, turn, below).within(a)) << "trial " << trial;
    }
}

// withinBoth (one pass for the list's reach and the contact reach, GroupGroupAlgorithm::relist)
// gives within()'s answer for both slacks, also exactly at the edge of the smaller one: its
// least slack (to the last bit) and one double below it, and with both slacks equal.
TEST(NearBox, WithinBothGivesWithinsAnswerForBothSlacks) {
    std::mt19937 rng(47);
    int counts[3] = {0, 0, 0};
    for (int trial = 0; trial < 6000; ++trial) {
        const BoxTurn turn(randomTurn(rng, trial));
        const geometry::Aabb a = randomBox(rng, 0.4), b = randomBox(rng, 0.4);
        double narrow = 0.01 * (trial % 5), wide = narrow + 0.005 * (trial % 3);
        if (trial % 4 == 1 && !withinOneByOne(a, b, turn, 0.0) && withinOneByOne(a, b, turn, 4.0)) {
            narrow = leastSlack([&](double slack) { return withinOneByOne(a, b, turn, slack); }, 4.0);
            if (trial % 8 == 1) narrow = std::bit_cast<double>(std::bit_cast<std::uint64_t>(narrow) - 1);
            wide = trial % 3 == 0 ? narrow : narrow + 0.003;
        }
        const bool inWide = NearBox(b, turn, wide).within(a), inNarrow = NearBox(b, turn, narrow).within(a);
        const int expected = !inWide ? 0 : inNarrow ? 2 : 1;
        ASSERT_EQ(NearBox(b, turn, wide).withinBoth(a, narrow), expected) << "trial " << trial;
        ++counts[expected];
    }
    for (int k = 0; k < 3; ++k) EXPECT_GT(counts[k], 300) << k;
}

// Whether a and b overlap by at least `depth` along every axis (AabbTree::pairsWith's test).
bool overlapBy(const geometry::Aabb& a, const geometry::Aabb& b, const Eigen::Vector3d& depth) {
    return ((b.max - a.min).array() >= depth.array()).all() && ((a.max - b.min).array() >= depth.array()).all();
}

// The relist's pruning (GroupGroupAlgorithm::relist): a pair NearBox keeps at the list's reach,
// taken exactly at the edge of that reach (its least slack, so a depth any deeper than the boxes
// allow shows), has A's box grown by slackA and the AABB of B's box grown by slackB and turned
// overlapping by relistDepth. The slacks differ (a depth that put them on the wrong sides
// shows), the turns are any (a depth without the turn's row sums, or with its column sums,
// shows at 45°).
TEST(NearBox, RelistDepthHoldsEveryPairKeptAtTheEdgeOfTheReach) {
    std::mt19937 rng(47);
    std::uniform_real_distribution<double> u(-1.0, 1.0), slack(0.006, 0.015), half(0.005, 0.05);
    const auto box = [&](double spread) {
        const Eigen::Vector3d c(spread * u(rng), spread * u(rng), spread * u(rng)), h(half(rng), half(rng), half(rng));
        return geometry::Aabb{c - h, c + h};
    };
    int atTheEdge = 0, turned = 0;
    for (int trial = 0; trial < 40000; ++trial) {
        Eigen::Isometry3d bToA = randomTurn(rng, trial);
        bToA.translation() *= 0.5;
        const BoxTurn turn(bToA);
        const geometry::Aabb a = box(0.05), b = box(0.05);
        const double slackA = slack(rng), slackB = slack(rng);
        if (NearBox(b, turn, 0.0).within(a) || !NearBox(b, turn, 0.012).within(a)) continue;
        const double reach = leastSlack([&](double slack) { return NearBox(b, turn, slack).within(a); }, 0.012);
        ASSERT_TRUE(NearBox(b, turn, reach).within(a));
        const Eigen::Vector3d depth = relistDepth(bToA.linear(), slackA, slackB, reach);
        EXPECT_TRUE(overlapBy(a.inflated(slackA), geometry::transformedAabb(b.inflated(slackB), bToA), depth))
            << "trial " << trial << " reach " << reach << " depth " << depth.transpose();
        ++atTheEdge;
        turned += trial % 4 != 0;
    }
    EXPECT_GT(atTheEdge, 2000);
    EXPECT_GT(turned, 1500);
}

// Two groups of boxes in trees over their boxes grown by the slacks, walked pruned to the
// relist's depth and filtered by NearBox at the reach, list the same pairs in the same order as
// the unpruned walk, and the pairs of a brute-force NearBox filter over all pairs; and the
// pruning skips some.
TEST(NearBox, TreesWalkedToTheRelistDepthListTheUnprunedPairs) {
    std::mt19937 rng(53);
    std::uniform_real_distribution<double> u(-1.0, 1.0), half(0.005, 0.03), reachOf(0.0, 0.012);
    const auto boxes = [&](int n) {
        std::vector<geometry::Aabb> out;
        for (int k = 0; k < n; ++k) {
            const Eigen::Vector3d c(0.15 * u(rng), 0.15 * u(rng), 0.05 * u(rng)), h(half(rng), half(rng), half(rng));
            out.push_back({c - h, c + h});
        }
        return out;
    };
    const auto grown = [](const std::vector<geometry::Aabb>& b, double by) {
        std::vector<geometry::Aabb> out;
        for (const geometry::Aabb& x : b) out.push_back(x.inflated(by));
        return out;
    };
    const double slackA = 0.01, slackB = 0.008;
    std::size_t listed = 0, prunedVisits = 0, unprunedVisits = 0;
    for (int trial = 0; trial < 60; ++trial) {
        const std::vector<geometry::Aabb> a = boxes(80), b = boxes(80);
        const geometry::AabbTree treeA(grown(a, slackA)), treeB(grown(b, slackB));
        Eigen::Isometry3d bToA = randomTurn(rng, trial);
        bToA.translation() *= 0.3;
        const BoxTurn turn(bToA);
        const double reach = reachOf(rng);
        std::vector<std::pair<int, int>> pruned, unpruned;
        std::set<std::pair<int, int>> brute;
        const auto keep = [&](std::vector<std::pair<int, int>>& list, std::size_t& visits) {
            return [&](int i, int j) {
                ++visits;
                if (NearBox(b[size_t(j)], turn, reach).within(a[size_t(i)])) list.emplace_back(i, j);
            };
        };
        treeA.pairsWith(treeB, bToA, keep(pruned, prunedVisits), relistDepth(bToA.linear(), slackA, slackB, reach));
        treeA.pairsWith(treeB, bToA, keep(unpruned, unprunedVisits));
        for (int i = 0; i < int(a.size()); ++i)
            for (int j = 0; j < int(b.size()); ++j)
                if (NearBox(b[size_t(j)], turn, reach).within(a[size_t(i)])) brute.emplace(i, j);
        EXPECT_EQ(pruned, unpruned) << "trial " << trial;
        EXPECT_EQ((std::set<std::pair<int, int>>(pruned.begin(), pruned.end())), brute) << "trial " << trial;
        listed += pruned.size();
    }
    EXPECT_GT(listed, 1000u);
    EXPECT_LT(prunedVisits, unprunedVisits); // the depth prunes
}

} // namespace
} // namespace shatter
