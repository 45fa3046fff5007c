// The constitutive models against their definitions: no stress at rest or under rotation,
// Hooke's law in the small-strain limit, stress as the derivative of the stored energy,
// and the snow return mapping.
#include <shatter/plugin/mpm/ConstitutiveModel.h>
#include <shatter/plugin/mpm/PolarDecomposition.h>

#include <gtest/gtest.h>

#include <cmath>

namespace shatter::mpm {
namespace {

Material material(ConstitutiveModelType model) {
    Material m;
    m.model = model;
    m.E = 2e6;
    m.nu = 0.3;
    m.rho = 1000;
    return m;
}

Mat2 rotation(double a) {
    Mat2 R;
    R << std::cos(a), -std::sin(a), std::sin(a), std::cos(a);
    return R;
}

TEST(ConstitutiveModel, RotationsAreStressFreeForTheRotationInvariantModels) {
    for (auto type : {ConstitutiveModelType::Corotated, ConstitutiveModelType::Snow}) {
        const auto c = ModelConstants::of(material(type), Analysis::PlaneStrain);
        for (double a : {0.0, 0.3, 1.7, 3.1, -2.2}) {
            // Stress scale is E = 2e6 Pa; 1e-9 relative is rounding in the polar decomposition.
            EXPECT_LT(kirchhoffStress(c, rotation(a), 1.0).norm(), 2e6 * 1e-9) << a;
            EXPECT_LT(energyDensity(c, rotation(a), 1.0), 2e6 * 1e-15) << a;
        }
    }
}

TEST(ConstitutiveModel, AllModelsAgreeWithHookesLawForSmallStrain) {
    // Uniaxial strain ε along x: σxx = (λ + 2μ)ε, σyy = λε. The hyperelastic models differ
    // from Hooke's law at second order, so with ε = 1e-6 the relative difference is ~1e-6.
    const double eps = 1e-6;
    Mat2 F = Mat2::Identity();
    F(0, 0) += eps;
    for (auto analysis : {Analysis::PlaneStress, Analysis::PlaneStrain})
        for (auto type : {ConstitutiveModelType::LinearElastic, ConstitutiveModelType::Corotated,
                          ConstitutiveModelType::Snow}) {
            const Material m = material(type);
            const auto c = ModelConstants::of(m, analysis);
            const Mat2 sigma = kirchhoffStress(c, F, 1.0) / F.determinant();
            const double lambda = m.lameLambda(analysis), mu = m.shearModulus();
            EXPECT_NEAR(sigma(0, 0), (lambda + 2 * mu) * eps, 1e-5 * (lambda + 2 * mu) * eps);
            EXPECT_NEAR(sigma(1, 1), lambda * eps, 1e-5 * (lambda + 2 * mu) * eps);
        }
}

TEST(ConstitutiveModel, PlaneStressGivesZeroThroughThicknessStress) {
    // Uniaxial stress in plane stress: σyy = 0 when εyy = −ν εxx and E is the slope.
    const Material m = material(ConstitutiveModelType::LinearElastic);
    const auto c = ModelConstants::of(m, Analysis::PlaneStress);
    Mat2 F = Mat2::Identity();
    F(0, 0) += 1e-4;
    F(1, 1) -= m.nu * 1e-4;
    const Mat2 sigma = kirchhoffStress(c, F, 1.0) / F.determinant();
    EXPECT_NEAR(sigma(1, 1), 0, 1e-6 * m.E * 1e-4);
    EXPECT_NEAR(sigma(0, 0) / 1e-4, m.E, 2e-4 * m.E); // J = 1 − 0.7e-4 enters at that order
}

TEST(ConstitutiveModel, KirchhoffStressIsTheEnergyDerivative) {
    // τ = (∂W/∂F) Fᵀ. Central differences with h = 1e-6 on W ~ E: truncation O(h²) and
    // rounding ~1e-16·E/h ~ 1e-10·E, so 1e-6·E is a loose but meaningful bound.
    Mat2 F;
    F << 1.1, 0.2, -0.15, 0.93;
    for (auto type : {ConstitutiveModelType::LinearElastic, ConstitutiveModelType::Corotated,
                      ConstitutiveModelType::Snow}) {
        const auto c = ModelConstants::of(material(type), Analysis::PlaneStrain);
        const double Jp = 0.97;
        Mat2 P;
        for (int i = 0; i < 2; ++i)
            for (int j = 0; j < 2; ++j) {
                const double h = 1e-6;
                Mat2 a = F, b = F;
                a(i, j) += h;
                b(i, j) -= h;
                P(i, j) = (energyDensity(c, a, Jp) - energyDensity(c, b, Jp)) / (2 * h);
            }
        const Mat2 tau = kirchhoffStress(c, F, Jp);
        if (type == ConstitutiveModelType::LinearElastic) {
            // Linear elasticity: ∂W/∂F = σ (symmetric), and τ = Jσ by our convention.
            EXPECT_LT((P * F.determinant() - tau).norm(), 1e-6 * 2e6);
        } else {
            EXPECT_LT((P * F.transpose() - tau).norm(), 1e-6 * 2e6);
        }
    }
}

TEST(ConstitutiveModel, SnowReturnMappingClampsAndKeepsTheTotalDeformation) {
    Material m = material(ConstitutiveModelType::Snow);
    const auto c = ModelConstants::of(m, Analysis::PlaneStrain);
    Mat2 Fe;
    Fe << 1.05, 0.02, -0.01, 0.9; // stretched beyond θs = 7.5e-3, compressed beyond θc = 2.5e-2
    Mat2 Fp = Mat2::Identity();
    const Mat2 total = Fe * Fp;
    returnToYieldSurface(c, Fe, Fp);
    const Svd2 d = svd(Fe);
    EXPECT_NEAR(d.sigma(0), 1 + m.thetaS, 1e-12);
    EXPECT_NEAR(d.sigma(1), 1 - m.thetaC, 1e-12);
    EXPECT_LT((Fe * Fp - total).norm(), 1e-12);
    EXPECT_GT(c.hardening(Fp.determinant()), 1.0); // compacted snow (J_P < 1) hardens
}

TEST(PolarDecomposition, SvdReconstructsIncludingInversion) {
    Mat2 F;
    F << 0.3, -1.2, 0.8, -0.5; // det < 0 would also be fine; this one is a general matrix
    for (int flip = 0; flip < 2; ++flip) {
        if (flip) F.col(0) *= -1; // inverted
        const Svd2 d = svd(F);
        EXPECT_LT((d.U * d.sigma.asDiagonal() * d.V.transpose() - F).norm(), 1e-14);
        EXPECT_NEAR(d.U.determinant(), 1, 1e-14);
        EXPECT_NEAR(d.V.determinant(), 1, 1e-14);
        EXPECT_GE(d.sigma(0), std::abs(d.sigma(1)));
    }
}

} // namespace
} // namespace shatter::mpm
