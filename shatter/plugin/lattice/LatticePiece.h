#pragma once
// One connected piece of a lattice (the whole body at first, then each fragment) and the
// solver state it keeps between steps.
#include <shatter/plugin/lattice/ConstraintSolver.h>
#include <shatter/plugin/lattice/NearestParticles.h>

#include <Eigen/Core>
#include <cmath>
#include <memory>
#include <vector>

namespace shatter::lattice {

struct LatticePiece {
    std::vector<int> particles;  // lattice particles (= tets), ascending
    bool anchored = false;       // holds a fixed particle, so the piece is static
    // The system over the piece's unbroken links, rebuilt after breaks; null until needed.
    std::unique_ptr<ConstraintSystem> system;
    Eigen::VectorXd lambda;      // last multipliers, one per system row: the next warm start
    Eigen::VectorXd analysedLoads; // the loads of its last analysis (empty: none yet)
    // A proven lower bound on the smallest eigenvalue of its system's Jacobi-scaled matrix
    // (EigenvalueBound.h), 0 when none: lets a solve stop once nothing can break. Computed by
    // makePiece for the whole lattice while no link is broken, passed on by inheritSolver.
    double eigenvalueBound = 0.0;
    // The fracture step's per-row buffers (FractureAnalysis), kept so that a rest step on a
    // large piece allocates and zeroes none: each row's link strength and the safe range
    // formed from them. The strengths are written by every solve; the safe range is formed
    // again only at the rows whose strength is not the one it was formed from (`formedFrom`,
    // max(0, strength); NaN: not formed), with the limit and ratio it was formed with.
    struct RowBuffers {
        std::vector<double> strength;
        SafeRange safe;
        std::vector<double> formedFrom;
        double limit = NAN, ratio = NAN;
    } rows;

    // pieceLoads' buffers, kept from one step to the next: the gravity part (mass × g on every
    // free particle) with the g (mesh axes) it is of, and the loads (gravity plus the step's
    // impacts) with the particles the impacts touched. An anchored piece's g has the same bits
    // every step, so a step writes only the particles of the last and this step's impacts
    // (forming and copying the loads of every particle of a 55,000-tet rest took 100 M
    // instructions in 12 frames). The particles, their masses and which are fixed do not change
    // in a piece's life (a smaller one is a new piece).
    struct KeptLoads {
        Eigen::Vector3d gravityOf = Eigen::Vector3d::Zero();
        Eigen::VectorXd gravity, loads; // empty: none kept
        std::vector<int> touched;       // positions in `particles`, repeats allowed
    } loads;

    // Builds the system if there is none: every unbroken link with both ends in the piece.
    ConstraintSystem& constraintSystem(const Lattice& lattice);
    // Rebuilds the system over the piece's particles without the links broken since and with
    // those joined again since (Lattice::joinLink), carrying λ over by link: in place when
    // nothing was joined (ConstraintSystem::restrictTo).
    void rebuild(const Lattice& lattice);
    // Takes (moves out) the solver state of `parent`, the piece this one was cut from, which is
    // left without a system: its λ carried over by
    // link into this piece's system, so that the next solve starts warm and the residual it
    // meets is only where the cut changed the loads (ConstraintSystem::solve).
    void inheritSolver(LatticePiece& parent, const Lattice& lattice);
    bool contains(int particle) const;
    // A grid over the piece's particle positions (indices are positions in `particles`),
    // built on first use: a piece is searched only when something hits it.
    const NearestParticles& nearestGrid(const Lattice& lattice);

private:
    std::unique_ptr<NearestParticles> grid_;
};

// A piece over `particles` (sorted here); anchored when any of them is fixed.
LatticePiece makePiece(const Lattice& lattice, std::vector<int> particles);

} // namespace shatter::lattice
