#pragma once
// One step of fracture for one piece (source 002 §3.2): solve the link forces under the
// step's loads, remove the links whose force exceeds their strength, spread damage from each
// break, and solve again until nothing more breaks (so cracks run as far as the loads drive
// them within the step); then weaken the survivors by their loads.
#include <shatter/plugin/lattice/BreakingRules.h>
#include <shatter/plugin/lattice/DamageSpreading.h>
#include <shatter/plugin/lattice/LatticePiece.h>
#include <shatter/plugin/lattice/Random.h>

#include <vector>

namespace shatter::lattice {

struct FractureAnalysisSettings {
    ConstraintSolverSettings solver;
    BreakingSettings breaking;
    DamageSpreadingSettings spreading;

    void check(const std::string& body) const;
};

struct FractureReport {
    int solves = 0;
    int iterations = 0;          // CG iterations over all solves
    double worstResidual = 0.0;  // largest relative residual of a solve
    bool converged = true;       // every solve reached the tolerance or proved nothing breaks
    int provenSafe = 0;          // solves stopped early: proven to break and weaken nothing (SafeRange)
    int breaksDecided = 0;       // solves stopped early: which links break proven (SafeRange)
    std::vector<int> broken;     // links removed this step: by force, by spreading, by weakening
    double maxUtilisation = 0.0; // largest force/capacity seen in the first solve
    double assemblySeconds = 0.0, solveSeconds = 0.0, breakingSeconds = 0.0;
};

// `loads` holds the external force on every particle of the piece in the piece's order (3 per
// particle, N, lattice axes): gravity, impacts. `omega` is the piece's angular velocity in the
// same axes (rad/s). Fixed particles take any load. Breaks are written into `lattice`; the
// piece keeps its particle list (splitting it is the caller's: connectedComponents).
FractureReport analyseFracture(Lattice& lattice, LatticePiece& piece, const Eigen::VectorXd& loads,
                               const Eigen::Vector3d& omega, const FractureAnalysisSettings& settings, Random& random);

} // namespace shatter::lattice
