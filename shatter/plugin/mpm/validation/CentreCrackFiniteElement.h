#pragma once
// An independent reference for the centre-cracked plate of finite width AND height: a static
// linear-elastic finite-element solve of the same plate, K_I from the J-integral.
//
// Why: Tada's F(λ) (CentreCrackedPlate.h) is for an infinitely tall strip; the validation
// plate is only twice as tall as it is wide. This solve has nothing in common with the MPM
// solver but the geometry and the load: quarter-symmetry model (x ≥ 0 about the crack's
// centre, y ≥ 0 above the crack line; u_x = 0 on x = 0, u_y = 0 on the ligament a ≤ x ≤ W/2,
// the crack face free), uniform traction σ on the top edge, sides free. Quadratic 6-node
// triangles on a tensor-product mesh graded toward the tip (node lines at distance
// L·(i/n)² from the tip in each of the three segments: crack, ligament, height; segment
// division counts ∝ √L so the smallest elements at the tip are square). Sparse Cholesky.
//
// J by the domain integral (Shih, Moran & Nakamura 1986; no body forces, static, straight
// traction-free faces): J = ∫_A (σ_ij ∂u_i/∂x − w δ_1j) ∂q/∂x_j dA, q = 1 within r1 of the
// tip falling linearly to 0 at r2, over the upper half doubled (symmetry); K_I = √(J E'),
// E' = E (plane stress) or E/(1 − ν²) (plane strain). A traction-loaded plate with a
// traction-free crack has stresses independent of the elastic constants (Michell), so K_I
// does not depend on the analysis or ν: a check of the solve, not a modelling choice.
//
// Convergence: three meshes, each with twice the divisions of the last; Richardson
// extrapolation with the observed order. `converged` when the finest two differ by less
// than `tolerance`; the extrapolated value is the reference.
#include <shatter/plugin/mpm/Material.h>

#include <array>

namespace shatter::mpm::validation {

struct CentreCrackFiniteElementCase {
    double width = 1;   // W
    double height = 2;  // H (the validation plate: 2W)
    double a = 0.25;    // crack half length, the crack centred in the plate, across the load
    double sigma = 1;   // remote tension on the top and bottom edges
    double E = 1, nu = 0.3;
    Analysis analysis = Analysis::PlaneStress;
    int divisions = 8;  // coarsest mesh: elements along the crack half (the others scale from it)
    double tolerance = 1e-3; // relative: the finest two meshes' K_I agree within this
};

struct CentreCrackFiniteElementMesh {
    int elements = 0;
    int nodes = 0;
    double KI = 0;           // from the outer domain (r1 = ℓ/4, r2 = ℓ/2, ℓ = min(a, W/2 − a, H/2))
    double KIinnerDomain = 0; // from a domain half that size: domain independence
};

struct CentreCrackFiniteElementResult {
    std::array<CentreCrackFiniteElementMesh, 3> meshes; // coarse to fine
    double KI = 0;           // extrapolated
    double order = 0;        // observed convergence order of K_I in the division count (0: not monotone)
    double errorEstimate = 0; // |extrapolated − finest| / extrapolated
    bool converged = false;
    // K_I / (σ√(πa)): comparable with tadaCentreCrack(2a/W).
    double F(const CentreCrackFiniteElementCase& c) const;
};

// One mesh, `divisions` elements along the crack half.
CentreCrackFiniteElementMesh solveCentreCrackFiniteElement(const CentreCrackFiniteElementCase& c, int divisions);
// The three meshes and the extrapolation. Throws std::invalid_argument on a geometry that is
// not a centre crack inside the plate.
CentreCrackFiniteElementResult centreCrackFiniteElement(const CentreCrackFiniteElementCase& c);

} // namespace shatter::mpm::validation
