#include <shatter/plugin/mpm/ConstitutiveModel.h>

#include <shatter/plugin/mpm/PolarDecomposition.h>

#include <algorithm>
#include <cmath>

namespace shatter::mpm {

ModelConstants ModelConstants::of(const Material& m, Analysis analysis) {
    ModelConstants c;
    c.model = m.model;
    c.mu = m.shearModulus();
    c.lambda = m.lameLambda(analysis);
    c.rho = m.rho;
    c.thetaC = m.thetaC;
    c.thetaS = m.thetaS;
    c.xi = m.xi;
    c.waveSpeed0 = std::sqrt((c.lambda + 2 * c.mu) / c.rho);
    return c;
}

double energyDensity(const ModelConstants& c, const Mat2& Fe, double Jp) {
    if (c.model == ConstitutiveModelType::LinearElastic) {
        const Mat2 eps = smallStrain(Fe);
        return c.mu * eps.squaredNorm() + 0.5 * c.lambda * eps.trace() * eps.trace();
    }
    const double h = c.hardening(Jp);
    const double J = Fe.determinant();
    return c.mu * h * (Fe - polarRotation(Fe)).squaredNorm() + 0.5 * c.lambda * h * (J - 1) * (J - 1);
}

void snowReturnMapping(const ModelConstants& c, Mat2& Fe, Mat2& Fp) {
    const Svd2 d = svd(Fe);
    const Vec2 clamped(std::clamp(d.sigma(0), 1 - c.thetaC, 1 + c.thetaS),
                       std::clamp(d.sigma(1), 1 - c.thetaC, 1 + c.thetaS));
    if (clamped == d.sigma) return;
    const Mat2 FeNew = d.U * clamped.asDiagonal() * d.V.transpose();
    const Mat2 FeNewInverse = d.V * clamped.cwiseInverse().asDiagonal() * d.U.transpose();
    Fp = FeNewInverse * Fe * Fp;
    Fe = FeNew;
}

} // namespace shatter::mpm
