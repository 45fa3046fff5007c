// The oriented-box test (NearBox.h), two axes at a time, against the 15 axes tried one by one
// in Eigen (the test as it was): the same answer for every pair, and the same least slack at
// which a pair comes within it, to the last bit.
#include <shatter/bullet_ext/shape/NearBox.h>

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <random>

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

// At the least slack that brings a pair within (found on the one-by-one test by bisection over
// the doubles), and one double below it, both tests agree: any axis computed with other bits
// would move that edge.
TEST(NearBox, FlipsAtTheSameSlackToTheLastBit) {
    std::mt19937 rng(43);
    for (int trial = 0; trial < 3000; ++trial) {
        const BoxTurn turn(randomTurn(rng, trial));
        const geometry::Aabb a = randomBox(rng, 0.5), b = randomBox(rng, 0.5);
        if (withinOneByOne(a, b, turn, 0.0)) continue;
        std::uint64_t low = std::bit_cast<std::uint64_t>(0.0), high = std::bit_cast<std::uint64_t>(4.0);
        ASSERT_TRUE(withinOneByOne(a, b, turn, 4.0));
        while (high - low > 1) { // positive doubles order as their bits
            const std::uint64_t mid = low + (high - low) / 2;
            (withinOneByOne(a, b, turn, std::bit_cast<double>(mid)) ? high : low) = mid;
        }
        const double least = std::bit_cast<double>(high), below = std::bit_cast<double>(low);
        EXPECT_TRUE(NearBox(b, turn, least).within(a)) << "trial " << trial;
        EXPECT_FALSE(NearBox(b, turn, below).within(a)) << "trial " << trial;
    }
}

} // namespace
} // namespace shatter
