// rowProof and outsideProof: the plain proof loops' sums over the rows, a packet of rows at a time.
#include <shatter/plugin/lattice/RowProof.h>
#include "tests/support/SameBits.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <vector>

namespace shatter::lattice {
namespace {

using shatter::test::sameBits;

// The loop ConstraintSystem::proven ran row by row.
RowProof plainProof(size_t rows, const double* r, const double* x, const double* d, const double* root,
                    const SafeRange& safe) {
    RowProof out;
    const bool decide = !safe.breakLower.empty();
    for (size_t k = 0; k < rows; ++k) {
        out.scaled += r[k] * r[k] / d[k];
        out.room = std::min(out.room, std::min(x[k] - safe.lower[k], safe.upper[k] - x[k]) * root[k]);
        out.beyond = out.beyond || (decide && (x[k] < safe.breakLower[k] || x[k] > safe.breakUpper[k]));
    }
    return out;
}

struct Rows {
    std::vector<double> r, x, d, root;
    SafeRange safe;
};

// Residuals over many magnitudes (so the order of the sum shows), λ inside, at and beyond the
// ranges' ends, ties of slack (equal ranges on several rows), a NaN λ now and then.
Rows randomRows(size_t n, bool decide, std::mt19937& random) {
    std::uniform_real_distribution<double> mantissa(-1.0, 1.0), positive(0.5, 2.0);
    std::uniform_int_distribution<int> exponent(-30, 30), kind(0, 11);
    Rows rows;
    for (size_t k = 0; k < n; ++k) {
        rows.r.push_back(std::ldexp(mantissa(random), exponent(random)));
        rows.d.push_back(positive(random));
        rows.root.push_back(std::sqrt(rows.d.back()));
        const int what = kind(random);
        const double lower = what < 3 ? -1.0 : -positive(random), upper = what < 3 ? 1.0 : positive(random);
        rows.safe.lower.push_back(lower);
        rows.safe.upper.push_back(upper);
        const double x = what == 0 ? 0.25 : what == 3 ? lower : what == 4 ? upper : what == 5 ? 2.0 * upper
                         : what == 6 ? std::nan("") : lower + (upper - lower) * (0.5 + 0.5 * mantissa(random));
        rows.x.push_back(x);
        if (decide) {
            rows.safe.breakLower.push_back(2.0 * lower);
            rows.safe.breakUpper.push_back(what == 7 ? 0.5 * x : 2.0 * upper);
        }
    }
    return rows;
}

TEST(RowProof, GivesThePlainLoopsSumsForEverySizeUpTo41) {
    std::mt19937 random(68);
    int beyondRuns = 0, infiniteRooms = 0;
    for (size_t n = 0; n <= 41; ++n)
        for (int trial = 0; trial < 20; ++trial) {
            const Rows rows = randomRows(n, trial % 3 != 0, random);
            const RowProof expected = plainProof(n, rows.r.data(), rows.x.data(), rows.d.data(), rows.root.data(), rows.safe);
            const RowProof got = rowProof(n, rows.r.data(), rows.x.data(), rows.d.data(), rows.root.data(), rows.safe);
            SCOPED_TRACE(testing::Message() << "n = " << n << ", trial " << trial);
            EXPECT_TRUE(sameBits(got.scaled, expected.scaled)) << got.scaled << " vs " << expected.scaled;
            EXPECT_EQ(got.room, expected.room); // (±0 equal: the proof only compares it)
            EXPECT_EQ(got.beyond, expected.beyond);
            beyondRuns += expected.beyond;
            infiniteRooms += std::isinf(expected.room);
        }
    EXPECT_GT(beyondRuns, 100); // both answers were tested
    EXPECT_GT(infiniteRooms, 10); // (empty lists)
}

// The loop ConstraintSystem::outsideOf ran row by row.
OutsideProof plainOutside(size_t rows, const char* skip, const double* r, const double* x, const double* d,
                          const double* root, const SafeRange& safe) {
    OutsideProof out;
    for (size_t k = 0; k < rows; ++k) {
        if (skip[k]) continue;
        const double lower = safe.breakLower[k], upper = safe.breakUpper[k];
        out.scaled += r[k] * r[k] / d[k];
        out.squared += r[k] * r[k];
        out.room = std::min(out.room, std::min(std::abs(x[k] - lower), std::abs(upper - x[k])) * root[k]);
        out.beyond = out.beyond || x[k] < lower || x[k] > upper;
    }
    return out;
}

TEST(RowProof, OutsideProofGivesThePlainLoopsSumsOverTheUnmarkedRows) {
    std::mt19937 random(19);
    std::uniform_int_distribution<int> mark(0, 3);
    int beyondRuns = 0, infiniteRooms = 0, nanSums = 0;
    for (size_t n = 0; n <= 41; ++n)
        for (int trial = 0; trial < 30; ++trial) {
            const Rows rows = randomRows(n, true, random);
            // Marks of every density: none, all, and a random share (the marks are any non-zero char).
            std::vector<char> skip(n);
            for (char& s : skip) s = trial == 0 ? 0 : trial == 1 ? 1 : char(mark(random) < trial % 4 ? 1 + mark(random) : 0);
            std::vector<double> r = rows.r;
            if (trial % 7 == 6 && n > 0) r[n / 2] = std::nan(""); // a NaN residual, skipped or not
            const OutsideProof expected =
                plainOutside(n, skip.data(), r.data(), rows.x.data(), rows.d.data(), rows.root.data(), rows.safe);
            const OutsideProof got = outsideProof(n, skip.data(), r.data(), rows.x.data(), rows.d.data(), rows.root.data(),
                                                  rows.safe.breakLower.data(), rows.safe.breakUpper.data());
            SCOPED_TRACE(testing::Message() << "n = " << n << ", trial " << trial);
            EXPECT_TRUE(sameBits(got.scaled, expected.scaled)) << got.scaled << " vs " << expected.scaled;
            EXPECT_TRUE(sameBits(got.squared, expected.squared)) << got.squared << " vs " << expected.squared;
            EXPECT_EQ(got.room, expected.room); // (±0 equal: the proof only compares it)
            EXPECT_EQ(got.beyond, expected.beyond);
            beyondRuns += expected.beyond;
            infiniteRooms += std::isinf(expected.room);
            nanSums += std::isnan(expected.scaled);
        }
    EXPECT_GT(beyondRuns, 100);
    EXPECT_GT(infiniteRooms, 30); // (every row skipped, or none)
    EXPECT_GT(nanSums, 10);
}

} // namespace
} // namespace shatter::lattice
