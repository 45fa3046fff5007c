// scanUtilisation: the break and weakening checks' plain loop over every row, a packet of rows at a time.
#include <shatter/plugin/lattice/RowUtilisation.h>
#include "tests/support/SameBits.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <utility>
#include <vector>

namespace shatter::lattice {
namespace {

using shatter::test::sameBits;

struct Picked {
    std::vector<std::pair<size_t, double>> rows; // (row, u) in call order
    double most = 0.0;
};

// The loop FractureAnalysis ran row by row.
Picked plainUtilisation(size_t rows, const double* strength, const double* lambda, double ratio, double onset, double most) {
    Picked out;
    for (size_t k = 0; k < rows; ++k) {
        const double u = utilisation(strength[k], lambda[k], ratio);
        most = std::max(most, u);
        if (!(u < onset) || u > 1.0) out.rows.emplace_back(k, u);
    }
    out.most = most;
    return out;
}

// λ of both signs over many magnitudes, ±0 and NaN; strengths positive, zero, negative and NaN.
double randomLambda(std::mt19937& random) {
    std::uniform_real_distribution<double> mantissa(-1.0, 1.0);
    std::uniform_int_distribution<int> exponent(-4, 4), kind(0, 19);
    switch (kind(random)) {
    case 0: return 0.0;
    case 1: return -0.0;
    case 2: return std::nan("");
    default: return std::ldexp(mantissa(random), exponent(random));
    }
}

double randomStrength(std::mt19937& random) {
    std::uniform_real_distribution<double> positive(0.5, 4.0);
    std::uniform_int_distribution<int> kind(0, 19);
    switch (kind(random)) {
    case 0: return 0.0;
    case 1: return -1.0;
    case 2: return std::nan("");
    case 3: return INFINITY;
    default: return positive(random);
    }
}

TEST(RowUtilisation, PicksThePlainLoopsRowsWithItsUtilisationsAndLargest) {
    std::mt19937 random(14);
    int picked = 0, zeroMost = 0;
    for (size_t n = 0; n <= 41; ++n)
        for (int trial = 0; trial < 30; ++trial) {
            std::vector<double> strength(n), lambda(n);
            const bool unloaded = trial % 5 == 4; // every λ ±0: the largest u is a zero of either sign
            for (size_t k = 0; k < n; ++k) {
                strength[k] = randomStrength(random);
                lambda[k] = unloaded ? (random() % 2 ? 0.0 : -0.0) : randomLambda(random);
            }
            const double ratio = trial % 2 ? 10.0 : 3.0, onset = trial % 3 ? 0.6 : 1.0;
            const double start = trial % 7 == 0 ? -0.0 : 0.0;
            const Picked expected = plainUtilisation(n, strength.data(), lambda.data(), ratio, onset, start);
            Picked got;
            got.most = scanUtilisation(n, strength.data(), lambda.data(), ratio, onset, start,
                                       [&](size_t row, double u) { got.rows.emplace_back(row, u); });
            SCOPED_TRACE(testing::Message() << "n = " << n << ", trial " << trial);
            EXPECT_TRUE(sameBits(got.most, expected.most)) << got.most << " vs " << expected.most;
            ASSERT_EQ(got.rows.size(), expected.rows.size());
            for (size_t i = 0; i < got.rows.size(); ++i) {
                EXPECT_EQ(got.rows[i].first, expected.rows[i].first);
                EXPECT_TRUE(sameBits(got.rows[i].second, expected.rows[i].second));
            }
            picked += int(expected.rows.size());
            zeroMost += expected.most == 0.0;
        }
    EXPECT_GT(picked, 1000);
    EXPECT_GT(zeroMost, 100);
}

} // namespace
} // namespace shatter::lattice
