// conjugateGradientStep: one pass with the bits of CG's five Eigen expressions.
#include <shatter/plugin/lattice/ConjugateGradientStep.h>

#include <gtest/gtest.h>

#include <cstring>
#include <random>

namespace shatter::lattice {
namespace {

bool sameBits(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
    // (memcmp may not be given the null data of an empty vector, even for no bytes)
    return a.size() == b.size() && (a.size() == 0 || std::memcmp(a.data(), b.data(), size_t(a.size()) * sizeof(double)) == 0);
}
bool sameBits(double a, double b) { return std::memcmp(&a, &b, sizeof(double)) == 0; }

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

TEST(ConjugateGradientStep, GivesTheBitsOfEigensExpressionsForEverySizeUpTo41) {
    std::mt19937 random(19);
    for (Eigen::Index n = 0; n <= 41; ++n)
        for (int trial = 0; trial < 20; ++trial) {
            const double alpha = trial == 0 ? 0.0 : std::ldexp(1.0 + 0.37 * trial, trial - 10);
            const Eigen::VectorXd p = mixed(n, random), ap = mixed(n, random);
            const Eigen::VectorXd inverseDiagonal = mixed(n, random).cwiseAbs();
            Eigen::VectorXd x = mixed(n, random), r = mixed(n, random);
            Eigen::VectorXd expectedX = x, expectedR = r, z;
            expectedX += alpha * p;
            expectedR -= alpha * ap;
            const double squares = expectedR.squaredNorm();
            const Eigen::VectorXd expectedZ = inverseDiagonal.cwiseProduct(expectedR);
            const double products = expectedR.dot(expectedZ);

            const StepSums sums = conjugateGradientStep(alpha, p, ap, inverseDiagonal, x, r, z);
            SCOPED_TRACE(testing::Message() << "n = " << n << ", trial " << trial);
            EXPECT_TRUE(sameBits(x, expectedX));
            EXPECT_TRUE(sameBits(r, expectedR));
            EXPECT_TRUE(sameBits(z, expectedZ));
            EXPECT_TRUE(sameBits(sums.residual, squares)) << sums.residual << " vs " << squares;
            EXPECT_TRUE(sameBits(sums.preconditioned, products)) << sums.preconditioned << " vs " << products;
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

} // namespace
} // namespace shatter::lattice
