#pragma once
// Runs the breakable bodies inside the world step (source 002 §3): after Bullet has solved the
// contacts of an internal step, the impulse each contact gave a lattice body becomes a force
// (impulse over the step) on the particles nearest to it (lattice::pieceLoads); with gravity
// and the body's spin it loads the lattice, whose link forces are solved, broken and weakened
// (lattice::analyseFracture); every piece that came apart becomes new rigid bodies that carry
// its momentum on (geometry::partState). Resting pieces freeze (RestingPieces).
#include <shatter/bullet_ext/System.h>
#include <shatter/bullet_ext/lattice/LatticeBody.h>
#include <shatter/bullet_ext/lattice/RestingPieces.h>
#include <shatter/plugin/geometry/RigidState.h>
#include <shatter/plugin/lattice/PieceLoads.h>

#include <LinearMath/btTransform.h>

#include <functional>
#include <memory>
#include <vector>

namespace shatter {

class LatticeSystem final : public System {
public:
    // Time spent per phase, summed since the last reset (seconds), and what happened.
    struct Timing {
        double impacts = 0.0, assembly = 0.0, solve = 0.0, breaking = 0.0, fragments = 0.0;
        double resting = 0.0; // rest detection, freezing and waking
        int analyses = 0, solves = 0, iterations = 0, linksBroken = 0, fragmentsCreated = 0;
        int frozen = 0, thawed = 0; // pieces frozen at rest and woken again
        int speedsLimited = 0;      // pieces slowed to LatticeSettings::hitSpeedFactor
        int debrisExpired = 0;      // debris pieces removed (lifetime, budget)
        int shrinksInWorld = 0;     // pieces that lost parts in the world, their pairs kept (keepPairsOnShrink)
        bool converged = true;
    };

    explicit LatticeSystem(SystemContext& context);
    LatticeSystem(const LatticeSystem&) = delete;
    LatticeSystem& operator=(const LatticeSystem&) = delete;

    LatticeBody& add(lattice::TetMesh mesh, const LatticeSettings& settings, const btTransform& pose);
    const std::vector<std::unique_ptr<LatticeBody>>& bodies() const { return bodies_; }

    // System
    bool active() const override { return !bodies_.empty(); }
    void step(double dt, const ContactSnapshot& contacts) override;
    // Speeds are capped, and frozen pieces woken, by the motion before the step.
    bool needsMotionBefore() const override;
    void forget(VisualBody& body) override;

    // The rigid states of every split since the last call (double precision, world frame; the
    // last 256 are kept): the parent just before, then each part as created. Their masses
    // and momenta add up.
    struct SplitRecord {
        geometry::RigidState parent;
        std::vector<geometry::RigidState> parts;
        std::vector<VisualBody*> bodies; // the parts' bodies, valid until they are removed
    };
    std::vector<SplitRecord> takeSplitRecords();

    const Timing& timing() const { return timing_; }
    void resetTiming() { timing_ = {}; }

    // Called before each analysis with the body's lattice, the piece, its loads and spin (mesh
    // axes) and the body's settings: lets a benchmark solve the same systems another way.
    using AnalysisObserver =
        std::function<void(const lattice::Lattice& lattice, lattice::LatticePiece& piece, const Eigen::VectorXd& loads,
                           const Eigen::Vector3d& omega, const LatticeSettings& settings)>;
    void setAnalysisObserver(AnalysisObserver observer) { observer_ = std::move(observer); }

    // Makes a frozen piece (LatticeSettings::freezeAtRest) a dynamic body again, at rest and
    // awake, e.g. before the application pushes it; false if `body` is not a frozen piece.
    bool thaw(const btCollisionObject& body);

private:
    struct PieceRef {
        LatticeBody* body;
        int piece;
    };
    struct Split {
        PieceRef ref;
        std::vector<std::vector<int>> parts;
        int kept = -1;    // the part that keeps the piece's body (-1: none, the body goes)
        int holding = -1; // the part that holds parts left for later by the fragment budget (-1: none)
    };
    std::vector<lattice::Impact> impactsOn(const LatticeBody::Piece& piece, const ContactSnapshot& contacts,
                                           const std::vector<int>& pairs, double dt) const;
    void analyse(const PieceRef& ref, const std::vector<lattice::Impact>& impacts, std::vector<Split>& splits);
    // Pieces that still hold parts (Piece::splitPending; step() does not analyse them).
    void addPendingSplits(std::vector<Split>& splits) const;
    // Chooses each split's kept part, and joins the parts beyond the body's fragment budget
    // (LatticeSettings::fragmentBudget) into one; a split left with nothing to make is dropped
    // and its piece marked pending.
    void budgetSplits(std::vector<Split>& splits);
    void replayImpacts(const ContactSnapshot& contacts, const std::vector<Split>& splits, double dt);
    void split(LatticeBody& body, std::vector<Split>& splits);
    void limitSpin(double dt);
    // Removes the debris pieces past their lifetime or over the budget (DebrisSettings).
    void removeExpiredDebris();
    // Caps the speed of every piece in contact (LatticeSettings::hitSpeedFactor).
    void limitSpeeds(double dt, const ContactSnapshot& contacts);
    // A piece of `particles` (sorted) with its own body of `mesh` (their physical mesh).
    // `fragment`: a part of a split (only those may be debris), not a body as the application added it.
    LatticeBody::Piece makePiece(LatticeBody& body, std::vector<int> particles, geometry::PhysicalMesh mesh,
                                 const btTransform& pose, bool fragment);
    // The anchored part of a split piece that keeps the piece's Bullet body: only the tets that
    // left are taken out of its group shape (lattice::partKeepingTheBody).
    LatticeBody::Piece shrinkPiece(LatticeBody& body, LatticeBody::Piece& old, std::vector<int> particles);
    // Removes a piece's body from the world as the system's own doing (forget ignores it).
    void removeOwn(VisualBody& body);

    SystemContext& context_;
    std::vector<std::unique_ptr<LatticeBody>> bodies_;
    RestingPieces resting_;
    Timing timing_;
    std::vector<SplitRecord> records_;
    AnalysisObserver observer_;
    VisualBody* removing_ = nullptr;
    int nextId_ = 0;
};

} // namespace shatter
