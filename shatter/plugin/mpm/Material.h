#pragma once
// What a body is made of: elastic constants, density, fracture toughness and the constitutive
// model that turns deformation into stress. Units: Pa, kg/m³, Pa·√m.
#include <limits>
#include <optional>
#include <string>
#include <string_view>

namespace shatter::mpm {

enum class ConstitutiveModelType {
    LinearElastic, // small strain, not rotation invariant: for validation against LEFM
    Corotated,     // fixed-corotated hyperelasticity (Stomakhin et al. 2012)
    Snow,          // fixed-corotated with plastic hardening (Stomakhin et al. 2013, θc, θs, ξ)
};

// The 2D idealisation. It decides the in-plane Lamé λ (plane stress uses the reduced
// λ* = 2λμ/(λ + 2μ) = Eν/(1 − ν²)) and the effective modulus in J = (K_I² + K_II²)/E'.
enum class Analysis { PlaneStress, PlaneStrain };

struct Material {
    std::string name;
    ConstitutiveModelType model = ConstitutiveModelType::Corotated;
    double E = 0;   // Young's modulus, Pa
    double nu = 0;  // Poisson's ratio, -1 < ν < 0.5
    double rho = 0; // density, kg/m³
    double Kc = std::numeric_limits<double>::infinity(); // fracture toughness, Pa·√m (∞: never grows)
    // Snow plasticity (used by ConstitutiveModelType::Snow only).
    double thetaC = 2.5e-2; // critical compression: singular values of F_E stay >= 1 − θc
    double thetaS = 7.5e-3; // critical stretch: singular values of F_E stay <= 1 + θs
    double xi = 10;         // hardening: moduli scale by exp(ξ(1 − J_P))

    double shearModulus() const { return E / (2 * (1 + nu)); }
    // In-plane λ for the analysis (see Analysis).
    double lameLambda(Analysis analysis) const;
    // E' with J = K²/E': E for plane stress, E/(1 − ν²) for plane strain.
    double effectiveModulus(Analysis analysis) const;
    // Kolosov's κ of the near-tip fields: 3 − 4ν (plane strain), (3 − ν)/(1 + ν) (plane stress).
    double kolosov(Analysis analysis) const;
};

// The source's material table (Table 1 of 001), with the models we give them:
//   snow  E 140 kPa, ν 0.2,  ρ 400,  Kc 10 Pa·√m,     Stomakhin's snow model (θc 2.5e-2, θs 7.5e-3, ξ 10)
//   pmma  E 2.94 GPa, ν 0.3, ρ 1190, Kc 1.2 MPa·√m,   fixed-corotated
//   glass E 70 GPa, ν 0.22,  ρ 2500, Kc 0.75 MPa·√m,  fixed-corotated
//   jello E 50 Pa, ν 0.4,    ρ 2,    Kc 10 Pa·√m,     fixed-corotated
// The table's column header says MPa·√m but its entries carry their own "M" (1.2M, 0.75M),
// so the values are read as Pa·√m: 1.2 MPa·√m is PMMA's handbook toughness.
std::optional<Material> materialPreset(std::string_view name);

} // namespace shatter::mpm
