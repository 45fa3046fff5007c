#pragma once
// Stress, stored energy and plastic return of the three constitutive models, evaluated per
// particle from its elastic deformation gradient F_E and plastic volume ratio J_P = det F_P.
#include "plugin/mpm/Material.h"
#include "plugin/mpm/Types.h"

namespace shatter::mpm {

// The per-particle constants of a material under one analysis, precomputed once.
struct ModelConstants {
    ConstitutiveModelType model = ConstitutiveModelType::Corotated;
    double mu = 0, lambda = 0, rho = 0;
    double thetaC = 0, thetaS = 0, xi = 0;

    static ModelConstants of(const Material& m, Analysis analysis);
    // exp(ξ(1 − J_P)) for snow, 1 otherwise (eq. 4 of 001).
    double hardening(double Jp) const;
};

// Kirchhoff stress τ = J σ = P F_Eᵀ (eq. 3-4 of 001 times J). The grid force of a particle is
// −V⁰ τ ∇w, which equals −V σ ∇w with the current volume V = J V⁰.
Mat2 kirchhoffStress(const ModelConstants& c, const Mat2& Fe, double Jp);

// Stored energy per unit reference volume, W (eq. 29 of 001; ½σ:ε for linear elasticity).
double energyDensity(const ModelConstants& c, const Mat2& Fe, double Jp);

// Snow plasticity (eq. 14-17 of 001): clamp the singular values of F_E to [1 − θc, 1 + θs]
// and move the excess into F_P, so that F_E F_P is unchanged. No-op for the elastic models.
// (001 eq. 17 prints V_pᵀ; the inverse of U Σ Vᵀ is V Σ⁻¹ Uᵀ, which is what is used.)
void returnToYieldSurface(const ModelConstants& c, Mat2& Fe, Mat2& Fp);

// Square of an upper estimate of the dilatational wave speed, m²/s², for the CFL condition:
// (λ + 2μ)·hardening·max(1, J_E²)/ρ. The J_E² factor covers the stiffening of the
// corotated volume term λ(J − 1)J under stretch.
double waveSpeedSquared(const ModelConstants& c, const Mat2& Fe, double Jp);

} // namespace shatter::mpm
