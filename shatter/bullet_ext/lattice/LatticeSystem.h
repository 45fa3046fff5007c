#pragma once
// Runs the breakable bodies inside the world step (source 002 §3): after Bullet has solved the
// contacts of an internal step, the impulse each contact gave a lattice body becomes a force
// (impulse over the step) on the particles nearest to it; with gravity and the body's spin it
// loads the lattice, whose link forces are solved, broken and weakened (FractureAnalysis);
// every piece that came apart becomes new rigid bodies that carry its momentum on.
#include <shatter/bullet_ext/oriented/PlasticDents.h>
#include <shatter/bullet_ext/lattice/LatticeBody.h>
#include <shatter/plugin/lattice/Fragments.h>

#include <LinearMath/btTransform.h>

#include <memory>
#include <unordered_map>
#include <vector>

namespace shatter {

class Plugin;
struct ContactImpulse;

class LatticeSystem {
public:
    // Time spent per phase, summed since the last reset (seconds), and what happened.
    struct Timing {
        double impacts = 0.0, assembly = 0.0, solve = 0.0, breaking = 0.0, fragments = 0.0;
        double resting = 0.0; // rest detection, freezing and waking
        int analyses = 0, solves = 0, iterations = 0, linksBroken = 0, fragmentsCreated = 0;
        int frozen = 0, thawed = 0; // pieces frozen at rest and woken again
        bool converged = true;
        // Only with setCholeskyComparison(true): the same systems by Eigen's SimplicialLDLT.
        int choleskySolves = 0;
        double choleskySeconds = 0.0;  // assembly of the sparse matrix, factorisation and solve
        double cgSeconds = 0.0;        // CG on the same systems from the same warm start
        double largestDifference = 0.0; // max ‖λ_CG − λ_LDLT‖ / ‖λ_LDLT‖
    };

    explicit LatticeSystem(Plugin& plugin);
    ~LatticeSystem(); // puts the pieces' group shapes back (the Plugin removes their bodies)
    LatticeSystem(const LatticeSystem&) = delete;
    LatticeSystem& operator=(const LatticeSystem&) = delete;

    LatticeBody& add(lattice::TetMesh mesh, const LatticeSettings& settings, const btTransform& pose);
    const std::vector<std::unique_ptr<LatticeBody>>& bodies() const { return bodies_; }
    void step(double dt);

    // The rigid states of every split since the last call (double precision, world frame; the
    // last 256 are kept): the parent just before, then each part as created. Their masses
    // and momenta add up.
    struct SplitRecord {
        lattice::RigidState parent;
        std::vector<lattice::RigidState> parts;
        std::vector<VisualBody*> bodies; // the parts' bodies, valid until they are removed
    };
    std::vector<SplitRecord> takeSplitRecords();

    const Timing& timing() const { return timing_; }
    void resetTiming() { timing_ = {}; }
    // Also solve every analysed system with a sparse Cholesky factorisation, for the benchmark.
    void setCholeskyComparison(bool on) { compareCholesky_ = on; }

    // Makes a frozen piece (LatticeSettings::freezeAtRest) a dynamic body again, at rest and
    // awake, e.g. before the application pushes it; false if `body` is not a frozen piece.
    bool thaw(const btCollisionObject& body);

    // For RestingPieces.cpp.
    struct FrozenRef {
        LatticeBody* body;
        LatticeBody::Piece* piece;
    };
    using FrozenIndex = std::unordered_map<const btCollisionObject*, FrozenRef>;

private:
    struct PieceRef {
        LatticeBody* body;
        int piece;
    };
    struct Split {
        PieceRef ref;
        std::vector<std::vector<int>> parts;
    };
    Eigen::VectorXd loadsOn(const PieceRef& ref, const std::vector<const ContactImpulse*>& contacts, double dt);
    void analyse(const PieceRef& ref, const std::vector<const ContactImpulse*>& contacts, double dt,
                 std::vector<Split>& splits);
    void compareWithCholesky(lattice::LatticePiece& piece, const Eigen::VectorXd& loads, const Eigen::Vector3d& omega,
                             const lattice::SolverSettings& settings);
    void replayImpacts(const std::vector<ContactImpulse>& contacts, const std::vector<Split>& splits);
    void split(LatticeBody& body, std::vector<Split>& splits);
    void limitSpin(double dt);
    // Pieces at rest for LatticeSettings::sleepAfter are made ready to sleep, and frozen
    // where they may be (RestingPieces.cpp).
    void settle(double dt);
    void freeze(const std::vector<LatticeBody::Piece*>& rested);
    FrozenIndex frozenPieces();
    // Frozen pieces hit in this step, or whose supports moved or broke off an anchored
    // piece, become dynamic again.
    void wakeHitPieces();
    // Records where a part broke off an anchored piece (its box): frozen pieces it held up
    // wake, since anchored parts are not among the supports a piece watches.
    void noteBrokenOff(const btRigidBody& part);
    void thaw(LatticeBody::Piece& piece);
    void recordVelocities();
    LatticeBody::Piece makePiece(LatticeBody& body, std::vector<int> particles, const btTransform& pose);
    // The anchored part of a split piece that keeps the piece's Bullet body: only the tets that
    // left are taken out of its group shape (see keptPart in the .cpp).
    LatticeBody::Piece shrinkPiece(LatticeBody& body, const LatticeBody::Piece& old, std::vector<int> particles);

    Plugin& plugin_;
    std::vector<std::unique_ptr<LatticeBody>> bodies_;
    Timing timing_;
    std::vector<SplitRecord> records_;
    VelocitySnapshot before_; // every body's motion at the end of the last step, while pieces are frozen
    std::vector<std::pair<btVector3, btVector3>> brokenOff_; // boxes of parts that broke off anchored pieces this step
    bool compareCholesky_ = false;
    int nextId_ = 0;
};

} // namespace shatter
