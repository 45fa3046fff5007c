#pragma once
// Stress, stored energy and plastic return of the three constitutive models, evaluated per
// particle from its elastic deformation gradient F_E and plastic volume ratio J_P = det F_P.
// The per-substep functions are inline: they run inside the transfer loops, and are
// compiled into both copies of those loops (TransferTargets.h).
#include <shatter/plugin/mpm/Material.h>
#include <shatter/plugin/mpm/PolarDecomposition.h>
#include <shatter/plugin/mpm/Types.h>

#include <algorithm>
#include <cmath>

namespace shatter::mpm {

// The per-particle constants of a material under one analysis, precomputed once.
struct ModelConstants {
    ConstitutiveModelType model = ConstitutiveModelType::Corotated;
    double mu = 0, lambda = 0, rho = 0;
    double waveSpeed0 = 0; // √((λ + 2μ)/ρ), m/s: the dilatational wave speed at rest
    double thetaC = 0, thetaS = 0, xi = 0;

    static ModelConstants of(const Material& m, Analysis analysis);
    // exp(ξ(1 − J_P)) for snow, 1 otherwise (eq. 4 of 001).
    double hardening(double Jp) const { return model == ConstitutiveModelType::Snow ? std::exp(xi * (1 - Jp)) : 1.0; }
};

// Small strain ε = sym(F) − I.
inline Mat2 smallStrain(const Mat2& F) { return 0.5 * (F + F.transpose()) - Mat2::Identity(); }

// Kirchhoff stress τ = J σ = P F_Eᵀ (eq. 3-4 of 001 times J). The grid force of a particle is
// −V⁰ τ ∇w, which equals −V σ ∇w with the current volume V = J V⁰.
[[gnu::always_inline]] inline Mat2 kirchhoffStress(const ModelConstants& c, const Mat2& Fe, double Jp) {
    const double J = Fe.determinant();
    if (c.model == ConstitutiveModelType::LinearElastic) {
        const Mat2 eps = smallStrain(Fe);
        return J * (c.lambda * eps.trace() * Mat2::Identity() + 2 * c.mu * eps);
    }
    const double h = c.hardening(Jp);
    const Mat2 R = polarRotation(Fe);
    return 2 * c.mu * h * (Fe - R) * Fe.transpose() + (c.lambda * h * (J - 1) * J) * Mat2::Identity();
}

// Stored energy per unit reference volume, W (eq. 29 of 001; ½σ:ε for linear elasticity).
double energyDensity(const ModelConstants& c, const Mat2& Fe, double Jp);

// Snow plasticity (eq. 14-17 of 001): clamp the singular values of F_E to [1 − θc, 1 + θs]
// and move the excess into F_P, so that F_E F_P is unchanged.
// (001 eq. 17 prints V_pᵀ; the inverse of U Σ Vᵀ is V Σ⁻¹ Uᵀ, which is what is used.)
void snowReturnMapping(const ModelConstants& c, Mat2& Fe, Mat2& Fp);
// Whether returnToYieldSurface changes anything for the model: the gather's fast path for two
// far particles (GridToParticle.cpp) skips the call when it does not, so the two stay in step.
inline bool hasReturnMapping(const ModelConstants& c) { return c.model == ConstitutiveModelType::Snow; }
// The plastic return of any model: snowReturnMapping for snow, nothing for the elastic ones.
inline void returnToYieldSurface(const ModelConstants& c, Mat2& Fe, Mat2& Fp) {
    if (hasReturnMapping(c)) snowReturnMapping(c, Fe, Fp);
}

// An upper estimate of the dilatational wave speed, m/s, for the CFL condition:
// √((λ + 2μ)·hardening·max(1, J_E²)/ρ). The J_E² factor covers the stiffening of the
// corotated volume term λ(J − 1)J under stretch.
inline double waveSpeed(const ModelConstants& c, const Mat2& Fe, double Jp) {
    const double stretch = std::max(1.0, std::abs(Fe.determinant()));
    if (c.model != ConstitutiveModelType::Snow) return c.waveSpeed0 * stretch;
    return c.waveSpeed0 * stretch * std::exp(0.5 * c.xi * (1 - Jp)); // √hardening
}

} // namespace shatter::mpm
