#pragma once
// A crack inclined at 45° to a remote tension σ (plane stress, linear elastic, quasi-static as
// in CentreCrackedPlate.h). In an infinite plate
//   K_I = σ√(πa)·sin²β,  K_II = σ√(πa)·sinβ·cosβ,  β = 45°:  K_I = K_II = ½σ√(πa),
// and the maximum hoop stress criterion kinks the crack by θ = −53.13° (opposite in sign to
// K_II). A finite plate pulled on two edges is not that problem: at width 6a its J is 11%
// above the one at width 12a (measured), and K_I, K_II shift by different amounts. So the
// plate here is a square carrying on its whole outline the exact tractions of the infinite
// plate (Westergaard's field, WestergaardField.h: in the crack's frame the remote uniaxial
// σ at 45° is biaxial σ/2 plus shear σ/2); its exact solution is then the infinite plate's,
// whatever its size. After settling, growth is switched on with a toughness below K_eff so
// that both tips take one growth step, whose angle to the old crack direction is measured.
#include <shatter/plugin/mpm/Scene.h>

namespace shatter::mpm::validation {

struct InclinedCrackCase {
    double aOverDx = 8;        // crack half length in cells
    double widthOverA = 5;     // side of the square plate / a
    double sigma = 1e3;        // Pa
    KernelType kernel = KernelType::Quadratic;
    int ppc = 3;
    int maxTransits = 12;
    int threads = 0;
    double shiftCells = 0;     // the crack moved along itself: where its tips fall in their cells
};

struct InclinedCrackResult {
    double KIreference = 0, KIIreference = 0; // infinite plate
    double KI[2] = {0, 0}, KII[2] = {0, 0};   // start and end tip
    double kink[2] = {0, 0};                  // measured first growth angle, rad
    double predictedKink[2] = {0, 0};         // kinkAngle(K_I, K_II) of the measured K's
    bool grew[2] = {false, false};
    long particles = 0;
    long substeps = 0;
    bool converged = false;
    bool valid = false;
};

Scene inclinedCrackScene(const InclinedCrackCase& c);
InclinedCrackResult runInclinedCrack(const InclinedCrackCase& c);

} // namespace shatter::mpm::validation
