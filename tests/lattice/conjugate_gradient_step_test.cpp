// conjugateGradientStep: one pass with the bits of CG's five Eigen expressions (residualAndNorm:
// of the residual measure's two); multiplyBlock
// and multiplyDirection: the bits of the plain product and of Eigen's direction update and dot.
#include <shatter/plugin/lattice/ConjugateGradientStep.h>
#include "tests/support/SameBits.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <random>
#include <string_view>
#include <vector>

namespace shatter::lattice {
namespace {

bool sameBits(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
    // (memcmp may not be given the null data of an empty vector, even for no bytes)
    return a.size() == b.size() && (a.size() == 0 || std::memcmp(a.data(), b.data(), size_t(a.size()) * sizeof(double)) == 0);
}
using shatter::test::sameBits;

// Values over many magnitudes and both signs, zeros of both signs among them, so that the
// order of the sums shows in the last bits.
Eigen::VectorXd mixed(Eigen::Index n, std::mt19937& random) {
    std::uniform_real_distribution<double> mantissa(-1.0, 1.0);
    std::uniform_int_distribution<int> exponent(-30, 30), kind(0, 9);
    Eigen::VectorXd v(n);
    for (Eigen::Index i = 0; i < n; ++i) {
        const int k = kind(random);
        v[i] = k == 0 ? 0.0 : k == 1 ? -0.0 : std::ldexp(mantissa(random), exponent(random));
    }
    return v;
}

// The paths this processor runs (both are checked against the plain formulas, so against each other).
std::vector<KernelPath> paths() {
    std::vector<KernelPath> out{KernelPath::Portable};
    if (kernelPathAvailable(KernelPath::Avx2)) out.push_back(KernelPath::Avx2);
    return out;
}

// The tests below run every path this processor has; the portable one runs everywhere, and
// the one the solver takes by default is one of them.
// The AVX2 path is compiled where ConjugateGradientStep.cpp says (GCC, x86, AVX not on at compile
// time) and chosen wherever the processor has AVX2: a build that silently lost it fails here.
TEST(KernelPaths, TheAvx2PathIsChosenWhereverItCanRun) {
    EXPECT_TRUE(kernelPathAvailable(KernelPath::Portable));
#if (defined(__x86_64__) || defined(__i386__)) && defined(__GNUC__) && !defined(__clang__) && !defined(__AVX__)
    __builtin_cpu_init();
    const char* forced = std::getenv("SHATTER_LATTICE_KERNEL");
    const bool portableForced = forced && std::string_view(forced) == "portable";
    const KernelPath expected =
        __builtin_cpu_supports("avx2") && !portableForced ? KernelPath::Avx2 : KernelPath::Portable;
#else
    const KernelPath expected = KernelPath::Portable;
#endif
    EXPECT_EQ(fastestKernelPath(), expected);
}

TEST(ConjugateGradientStep, GivesTheBitsOfEigensExpressionsForEverySizeUpTo41) {
    std::mt19937 random(19);
    for (Eigen::Index n = 0; n <= 41; ++n)
        for (int trial = 0; trial < 20; ++trial) {
            const double alpha = trial == 0 ? 0.0 : std::ldexp(1.0 + 0.37 * trial, trial - 10);
            const Eigen::VectorXd p = mixed(n, random), ap = mixed(n, random);
            const Eigen::VectorXd inverseDiagonal = mixed(n, random).cwiseAbs();
            const Eigen::VectorXd x0 = mixed(n, random), r0 = mixed(n, random);
            Eigen::VectorXd expectedX = x0, expectedR = r0;
            expectedX += alpha * p;
            expectedR -= alpha * ap;
            const double squares = expectedR.squaredNorm();
            const Eigen::VectorXd expectedZ = inverseDiagonal.cwiseProduct(expectedR);
            const double products = expectedR.dot(expectedZ);

            for (KernelPath path : paths()) {
                Eigen::VectorXd x = x0, r = r0, z;
                const StepSums sums = conjugateGradientStep(alpha, p, ap, inverseDiagonal, x, r, z, path);
                SCOPED_TRACE(testing::Message() << "n = " << n << ", trial " << trial << ", path " << int(path));
                EXPECT_TRUE(sameBits(x, expectedX));
                EXPECT_TRUE(sameBits(r, expectedR));
                EXPECT_TRUE(sameBits(z, expectedZ));
                EXPECT_TRUE(sameBits(sums.residual, squares)) << sums.residual << " vs " << squares;
                EXPECT_TRUE(sameBits(sums.preconditioned, products)) << sums.preconditioned << " vs " << products;
            }
        }
}

// The solve's residual measure: r = b − Ax and ‖r‖ in one pass, with the bits of the two
// Eigen expressions (the norm's sum in Eigen's order), r resized from any size.
TEST(ConjugateGradientStep, ResidualAndNormGivesTheBitsOfEigensExpressions) {
    std::mt19937 random(23);
    for (Eigen::Index n = 0; n <= 41; ++n)
        for (int trial = 0; trial < 20; ++trial) {
            const Eigen::VectorXd b = mixed(n, random), ax = mixed(n, random);
            Eigen::VectorXd expected = ax;
            expected = b - expected;
            const double norm = expected.norm();
            Eigen::VectorXd r = mixed(trial % 3 == 0 ? n : n + 5, random);
            const double got = residualAndNorm(b, ax, r);
            SCOPED_TRACE(testing::Message() << "n = " << n << ", trial " << trial);
            EXPECT_TRUE(sameBits(r, expected));
            EXPECT_TRUE(sameBits(got, norm)) << got << " vs " << norm;
        }
}

// A sum in another order differs in its last bits on these values: the test above would see
// a pass that sums element after element.
TEST(ConjugateGradientStep, TheValuesTellTheOrderOfASum) {
    std::mt19937 random(19);
    int differing = 0;
    for (int trial = 0; trial < 50; ++trial) {
        const Eigen::VectorXd v = mixed(37, random);
        double sequential = 0.0;
        for (Eigen::Index i = 0; i < v.size(); ++i) sequential += v[i] * v[i];
        differing += !sameBits(sequential, v.squaredNorm());
    }
    EXPECT_GT(differing, 10);
}

// Rows between random particles (some fixed), in the block's layout (ends as the address of
// their particle's sum, sums padded to kBlockStride doubles, a double after the last normal).
struct RandomBlock {
    std::vector<int> particleA, particleB;
    std::vector<double*> ends;
    std::vector<Eigen::Vector3d> normal;
    std::vector<double> paddedNormal, paddedSums;
    std::vector<double> inverseMass; // per particle
    RandomBlock(Eigen::Index rows, std::mt19937& random) {
        const int particles = 2 + int(rows / 2);
        std::uniform_int_distribution<int> particle(0, particles - 1), kind(0, 4);
        std::uniform_real_distribution<double> unit(-1.0, 1.0), mass(0.1, 10.0);
        for (int i = 0; i < particles; ++i) inverseMass.push_back(kind(random) == 0 ? 0.0 : 1.0 / mass(random));
        for (Eigen::Index k = 0; k < rows; ++k) {
            const int first = particle(random);
            int second = particle(random);
            if (second == first) second = (first + 1) % particles;
            particleA.push_back(first), particleB.push_back(second);
            normal.push_back(Eigen::Vector3d(unit(random), unit(random), unit(random)).normalized());
            paddedNormal.insert(paddedNormal.end(), {normal.back()[0], normal.back()[1], normal.back()[2]});
        }
        // The double after the last normal, which the AVX2 path loads: anything, never in a result.
        paddedNormal.push_back(std::nan(""));
        // Sums start as anything: the product clears them.
        paddedSums.assign(size_t(kBlockStride * particles), std::nan(""));
        for (Eigen::Index k = 0; k < rows; ++k)
            for (int end : {particleA[size_t(k)], particleB[size_t(k)]}) ends.push_back(paddedSums.data() + kBlockStride * end);
    }
    RandomBlock(const RandomBlock&) = delete; // `ends` points into its own sums
    BlockRows rows() {
        BlockRows view;
        view.ends = ends.data(), view.normal = paddedNormal.data(), view.rows = Eigen::Index(particleA.size());
        view.inverseMass = inverseMass.data(), view.sums = paddedSums.data(), view.particles = Eigen::Index(inverseMass.size());
        return view;
    }
    // The sums a product left, without their pad lanes.
    std::vector<Eigen::Vector3d> sums() const {
        std::vector<Eigen::Vector3d> out;
        for (size_t i = 0; i < inverseMass.size(); ++i)
            out.emplace_back(paddedSums[kBlockStride * i], paddedSums[kBlockStride * i + 1], paddedSums[kBlockStride * i + 2]);
        return out;
    }
    // The plain formulas (ConstraintSystem's multiply): y = J M⁻¹ Jᵀ x, the sums M⁻¹ Jᵀ x.
    Eigen::VectorXd product(const Eigen::VectorXd& x, std::vector<Eigen::Vector3d>& plainSums) const {
        plainSums.assign(inverseMass.size(), Eigen::Vector3d::Zero());
        for (size_t k = 0; k < particleA.size(); ++k) {
            const Eigen::Vector3d f = normal[k] * x[Eigen::Index(k)];
            plainSums[size_t(particleA[k])] += f;
            plainSums[size_t(particleB[k])] -= f;
        }
        for (size_t i = 0; i < plainSums.size(); ++i) plainSums[i] *= inverseMass[i];
        Eigen::VectorXd y(x.size());
        for (size_t k = 0; k < particleA.size(); ++k)
            y[Eigen::Index(k)] = normal[k].dot(plainSums[size_t(particleA[k])] - plainSums[size_t(particleB[k])]);
        return y;
    }
};

bool sameBits(const std::vector<Eigen::Vector3d>& a, const std::vector<Eigen::Vector3d>& b) {
    return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(Eigen::Vector3d)) == 0);
}

TEST(BlockProduct, MultiplyBlockGivesTheBitsOfThePlainProduct) {
    std::mt19937 random(14);
    for (Eigen::Index n = 0; n <= 41; ++n)
        for (int trial = 0; trial < 10; ++trial) {
            RandomBlock block(n, random);
            const Eigen::VectorXd x = mixed(n, random);
            std::vector<Eigen::Vector3d> plainSums;
            const Eigen::VectorXd expected = block.product(x, plainSums);
            for (KernelPath path : paths()) {
                Eigen::VectorXd y(n);
                multiplyBlock(block.rows(), x.data(), y.data(), path);
                SCOPED_TRACE(testing::Message() << "n = " << n << ", trial " << trial << ", path " << int(path));
                EXPECT_TRUE(sameBits(y, expected));
                EXPECT_TRUE(sameBits(block.sums(), plainSums));
            }
        }
}

// The whole system's product (ConstraintSystem::multiply) on the particle numbers, against the
// plain formulas, on every path: normals with no pad after the last row (an exact-size buffer, so
// memcheck sees a load past it), sums scratch starting as NaN.
TEST(BlockProduct, MultiplyIndexedRowsGivesTheBitsOfThePlainProduct) {
    std::mt19937 random(52);
    for (Eigen::Index n = 0; n <= 41; ++n)
        for (int trial = 0; trial < 10; ++trial) {
            RandomBlock block(n, random);
            const Eigen::VectorXd x = mixed(n, random);
            std::vector<Eigen::Vector3d> plainSums;
            const Eigen::VectorXd expected = block.product(x, plainSums);
            const std::unique_ptr<double[]> normals(new double[size_t(3 * n)]);
            for (Eigen::Index k = 0; k < n; ++k)
                for (int c = 0; c < 3; ++c) normals[size_t(3 * k + c)] = block.normal[size_t(k)][c];
            for (KernelPath path : paths()) {
                std::vector<double> padded(size_t(kBlockStride) * block.inverseMass.size(), std::nan(""));
                std::vector<Eigen::Vector3d> acceleration(block.inverseMass.size(), Eigen::Vector3d::Constant(std::nan("")));
                IndexedRows rows;
                rows.a = block.particleA.data(), rows.b = block.particleB.data(), rows.normal = normals.get();
                rows.rows = n, rows.inverseMass = block.inverseMass.data();
                rows.particles = Eigen::Index(block.inverseMass.size()), rows.sums = padded.data();
                Eigen::VectorXd y(n);
                multiplyIndexedRows(rows, x.data(), y.data(), acceleration.data()->data(), path);
                SCOPED_TRACE(testing::Message() << "n = " << n << ", trial " << trial << ", path " << int(path));
                EXPECT_TRUE(sameBits(y, expected));
                EXPECT_TRUE(sameBits(acceleration, plainSums));
            }
        }
}

// The fused direction update, product and dot against `p = z + beta * p`, the plain product
// and Eigen's p.dot(ap), and (z null) against the product and dot of p as it is.
TEST(BlockProduct, MultiplyDirectionGivesTheBitsOfTheUpdateProductAndDot) {
    std::mt19937 random(19);
    for (Eigen::Index n = 0; n <= 41; ++n)
        for (int trial = 0; trial < 20; ++trial) {
            RandomBlock block(n, random);
            const bool first = trial % 5 == 0;
            const double beta = trial == 1 ? 0.0 : std::ldexp(1.0 + 0.29 * trial, trial - 12);
            const Eigen::VectorXd z = mixed(n, random), start = mixed(n, random);
            Eigen::VectorXd expectedP = start;
            if (!first) expectedP = z + beta * expectedP;
            std::vector<Eigen::Vector3d> plainSums;
            const Eigen::VectorXd expectedAp = block.product(expectedP, plainSums);
            const double expectedDot = expectedP.dot(expectedAp);
            for (KernelPath path : paths()) {
                Eigen::VectorXd p = start, ap(n);
                const double dot =
                    multiplyDirection(block.rows(), first ? nullptr : z.data(), beta, p.data(), ap.data(), path);
                SCOPED_TRACE(testing::Message() << "n = " << n << ", trial " << trial << ", path " << int(path));
                EXPECT_TRUE(sameBits(p, expectedP));
                EXPECT_TRUE(sameBits(ap, expectedAp));
                EXPECT_TRUE(sameBits(block.sums(), plainSums));
                EXPECT_TRUE(sameBits(dot, expectedDot)) << dot << " vs " << expectedDot;
            }
        }
}

// Region CG's "rows look decided" check against its plain loop (solveRegion's before it moved
// here), on rows near the reach (ties of the scaled distance and `reach` included), with λ
// exactly at a range's end, ±0, NaN and infinite ranges among them.
TEST(RowsLookDecided, GivesThePlainLoopsAnswerOnEveryPath) {
    std::mt19937 random(1419);
    std::uniform_real_distribution<double> unit(-1.0, 1.0), positive(0.1, 2.0);
    std::uniform_int_distribution<int> kind(0, 11);
    int decided = 0, undecided = 0, beyondSeen = 0;
    for (Eigen::Index n = 0; n <= 23; ++n)
        for (int trial = 0; trial < 60; ++trial) {
            const size_t rows = static_cast<size_t>(n);
            std::vector<double> x(rows), lower(rows), upper(rows), root(rows);
            for (size_t j = 0; j < size_t(n); ++j) {
                lower[j] = -positive(random), upper[j] = positive(random), root[j] = positive(random);
                x[j] = 3.0 * unit(random);
                const int k = kind(random);
                if (k == 0) x[j] = lower[j];
                if (k == 1) x[j] = (trial % 2) ? 0.0 : -0.0;
                if (k == 2 && trial % 7 == 0) x[j] = std::nan("");
                if (k == 3) upper[j] = INFINITY;
            }
            auto plain = [&](double reach, bool& beyond) {
                for (size_t j = 0; j < size_t(n); ++j) {
                    const double distance = std::min(std::abs(x[j] - lower[j]), std::abs(upper[j] - x[j]));
                    if (!(distance / root[j] > reach)) return false;
                    beyond = beyond || x[j] < lower[j] || x[j] > upper[j];
                }
                return true;
            };
            // A reach just below the smallest scaled distance (most rows pass), at it (a tie), or 0.
            double least = INFINITY;
            for (size_t j = 0; j < size_t(n); ++j)
                least = std::min(least, std::min(std::abs(x[j] - lower[j]), std::abs(upper[j] - x[j])) / root[j]);
            const double reach = trial % 3 == 0 ? least : trial % 3 == 1 ? std::nextafter(least, -INFINITY) : 0.0;
            bool expectedBeyond = false;
            const bool expected = plain(reach, expectedBeyond);
            (expected ? decided : undecided) += 1;
            beyondSeen += expected && expectedBeyond;
            for (KernelPath path : paths()) {
                bool beyond = false;
                const bool got = rowsLookDecided(n, x.data(), lower.data(), upper.data(), root.data(), reach, beyond, path);
                SCOPED_TRACE(testing::Message() << "n = " << n << ", trial " << trial << ", path " << int(path));
                EXPECT_EQ(got, expected);
                if (expected) {
                    EXPECT_EQ(beyond, expectedBeyond);
                }
            }
        }
    // Both answers, and rows beyond their range, occur.
    EXPECT_GT(decided, 100);
    EXPECT_GT(undecided, 100);
    EXPECT_GT(beyondSeen, 20);
}

} // namespace
} // namespace shatter::lattice
