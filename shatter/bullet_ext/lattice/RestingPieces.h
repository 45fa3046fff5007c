#pragma once
// Resting lattice pieces (LatticeSettings: sleepAfter, sleepDrift, sleepTurn, freezeAtRest,
// wakeSpeed, wakeDrift, wakeMassRatio): a loose piece that has stayed put is made ready to
// sleep, and frozen as a static body (FrozenBody.h) where it may be; a frozen piece wakes when
// it is hit or loses a support (neither by a body far lighter than it), is overlapped by a
// moving kinematic body or by a part that broke off an anchored piece, or when the
// application thaws it.
#include <shatter/bullet_ext/ContactSnapshot.h>
#include <shatter/bullet_ext/System.h>
#include <shatter/bullet_ext/lattice/LatticeBody.h>

#include <memory>
#include <unordered_map>
#include <utility>
#include <vector>

namespace shatter {

class RestingPieces {
public:
    // Over the lattice bodies of a LatticeSystem (the vector is the system's; it may grow).
    RestingPieces(SystemContext& context, std::vector<std::unique_ptr<LatticeBody>>& bodies)
        : context_(context), bodies_(bodies) {}

    struct Counts {
        int frozen = 0, thawed = 0;
    };
    // After the step's breaks: wakes the frozen pieces that must move, then lets resting pieces
    // sleep or freeze. Runs inside the step after integration and before the world's
    // updateActivationState, which adds the step to each body's deactivation timer.
    Counts step(double dt, const ContactSnapshot& contacts);
    // A part broke off an anchored piece in this step: frozen pieces its box overlaps wake
    // next (anchored parts are fixed for good, so they are not among the supports watched).
    void noteBrokenOff(const btRigidBody& part);
    // Makes a frozen piece dynamic again, at rest and awake; false if `body` is none.
    bool thaw(const btCollisionObject& body);
    bool anyFrozen() const;

    struct FrozenRef {
        LatticeBody* body;
        LatticeBody::Piece* piece;
    };
    using FrozenIndex = std::unordered_map<const btCollisionObject*, FrozenRef>;

private:
    // Pieces at rest for LatticeSettings::sleepAfter are made ready to sleep, and frozen
    // where they may be; returns how many froze.
    int settle(double dt, const ContactSnapshot& contacts);
    struct Rested {
        LatticeBody::Piece* piece;
        double lightBelow; // kg: lighter bodies are no support of it (RestSettings::wakeMassRatio)
    };
    int freeze(const std::vector<Rested>& rested, const ContactSnapshot& contacts);
    FrozenIndex frozenPieces();
    // Frozen pieces hit in this step, or whose supports moved or broke off an anchored piece,
    // become dynamic again; returns how many.
    int wakeHitPieces(const ContactSnapshot& contacts, double dt);
    void thaw(LatticeBody::Piece& piece);

    SystemContext& context_;
    std::vector<std::unique_ptr<LatticeBody>>& bodies_;
    std::vector<std::pair<btVector3, btVector3>> brokenOff_; // boxes of parts that broke off anchored pieces this step
};

} // namespace shatter
