#pragma once
// Position based dynamics with orientations (source 000 §3.2.2) over generalized
// shape-matching groups (§3.2.3): the time step of a soft oriented-particle body.
#include <shatter/plugin/oriented/OrientedParticles.h>
#include <shatter/plugin/oriented/PairConstraints.h>
#include <shatter/plugin/oriented/ShapeMatchingGroups.h>
#include <shatter/plugin/oriented/SolverSettings.h>

#include <span>
#include <vector>

namespace shatter::oriented {

// A contact of a particle, from the collision detection at the start of the step. A particle
// that starts inside is first moved out (no velocity is made of that); then
// n·(Δx − Δother) + distance ≥ 0 keeps it from crossing the other side, and Coulomb
// friction (coefficient `friction`) limits the relative tangential motion, static when it
// can be. The other side is, by default, a surface that nothing here moves (it may have
// moved by `surfaceMove` in this step on its own: a kinematic platform); with `body` set, a
// rigid body of another simulation that takes its share of every correction (two-way
// coupling, momentum exchanged exactly); with `otherParticle` set, a particle of the same
// object (self-contact, both mass-weighted).
struct ParticleContact {
    int particle = 0;
    Eigen::Vector3d normal = Eigen::Vector3d::UnitZ(); // unit, from the other side towards the particle
    double distance = 0.0;                             // m, signed separation (< 0: penetrating)
    double friction = 0.5;
    int body = -1;          // index into step()'s bodies, or -1
    int otherParticle = -1; // a particle of this object, or -1
    Eigen::Vector3d point = Eigen::Vector3d::Zero();       // m, world point on the body (its lever arm)
    Eigen::Vector3d surfaceMove = Eigen::Vector3d::Zero(); // m, the other side's motion in this step before the particles'
};

// A rigid body of another simulation (a Bullet body) that particles touch. The solver moves it
// with the particles: every contact correction is shared by inverse mass (and inertia about
// the contact point), so Σ m Δx of particles and body together is zero.
struct ContactBody {
    double inverseMass = 0.0;                                     // 1/kg
    Eigen::Matrix3d inverseInertia = Eigen::Matrix3d::Zero();     // world axes, 1/(kg m²)
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();             // m, world centre of mass now
    Eigen::Vector3d shift = Eigen::Vector3d::Zero();              // out: m, correction of its centre in the step
    Eigen::Vector3d turn = Eigen::Vector3d::Zero();               // out: rad, correction of its orientation (rotation vector)
};

class OrientedSolver {
public:
    // One shape-matching group per particle over `connections`. Throws shatter::InputError
    // naming `object` for bad settings or connections. A graph with several components
    // simulates each on its own (groups never cross components).
    OrientedSolver(std::string object, OrientedParticles particles,
                   const std::vector<std::pair<int, int>>& connections, const SolverSettings& settings);
    // Becomes the solver the constructor makes of these arguments (no constraints, no last
    // step, not quiet), in the memory it already holds (ShapeMatchingGroups::rebuild). Throws
    // as the constructor does, and then is unchanged.
    void rebuild(std::string object, OrientedParticles particles,
                 const std::vector<std::pair<int, int>>& connections, const SolverSettings& settings);

    // Advances by dt (s): predict with gravity and velocities, project contacts, pair
    // constraints and shape matching `iterations` times, update velocities from the change
    // of position and orientation. `bodies` are the rigid bodies contacts name: their shift
    // and turn are set to the corrections the contacts made (the caller moves the bodies by
    // them and adds shift/dt and turn/dt to their velocities). Throws InputError naming the
    // object for a contact with a non-finite value, an unknown particle or body, or a body
    // with a negative or non-finite inverse mass.
    // With `substeps` n > 1 it takes n such steps of dt, all with these contacts, found before
    // the first: a later step's contact distance is the found one plus the particles' own
    // motion along the normal since (both particles' for a self-contact). So each step is as
    // stiff as a step of dt with fresh contacts, which one step of n·dt is not (a PBD step's
    // stiffness is per step). The other side must then stand still: a contact with a body or
    // a surface move is an InputError naming the object, as is n < 1. contactImpulses() are
    // then summed over the n steps.
    void step(double dt, std::span<const ParticleContact> contacts = {}, std::span<ContactBody> bodies = {},
              int substeps = 1);

    // Quasi-static relaxation: `sweeps` shape-matching sweeps over the given groups on the
    // current pose, no velocities involved (used by plastic deformation).
    void relax(std::span<const int> groups, int sweeps);

    OrientedParticles& particles() { return particles_; }
    const OrientedParticles& particles() const { return particles_; }
    ShapeMatchingGroups& groups() { return groups_; }
    const ShapeMatchingGroups& groups() const { return groups_; }
    const SolverSettings& settings() const { return settings_; }
    void setSettings(const SolverSettings& settings);
    std::vector<StretchConstraint>& stretchConstraints() { return stretch_; }
    std::vector<BendConstraint>& bendConstraints() { return bend_; }
    const std::string& object() const { return object_; }

    // The impulse (N·s) each contact of the last step() gave its particle, normal and friction
    // together: Σ λ d / dt over the contact's corrections, each of which moved the particle by
    // λ d / m and the other side by −λ d / m_other (a surface nothing moves takes it whole).
    std::span<const Eigen::Vector3d> contactImpulses() const { return contactImpulses_; }

    // How long (s) every particle has moved slower than settings().sleepSpeed, counted over
    // step()s: a particle's speed here is √(|v|² + |ω|² tr(C)/m), which bounds its kinetic
    // energy (translation and spin) as ½ m speed² (ωᵀIω ≤ |ω|² tr C). 0 while sleepSpeed is 0.
    double quietTime() const { return quietTime_; }
    // Stops every particle (velocities, and the second-order update's memory) and restarts
    // quietTime(): the state of a body put to sleep, from which it wakes at rest.
    void stop();

    // Deformation matrix of particle i's group at the current pose (source 000 §3.3).
    Eigen::Matrix3d deformation(int i) const;

private:
    struct Side; // the other side of a contact, as its projection sees it
    Side otherSide(const ParticleContact& c, std::span<ContactBody> bodies) const;
    void substep(double dt, std::span<const ParticleContact> contacts, std::span<ContactBody> bodies, bool later);
    void separate(std::span<const ParticleContact> contacts, bool later);
    void predict(double dt);
    void projectContacts(std::span<const ParticleContact> contacts, std::span<ContactBody> bodies);
    void updateVelocities(double dt);
    void checkContacts(std::span<const ParticleContact> contacts, std::span<const ContactBody> bodies,
                       int substeps) const;
    double inverseMass(int i) const { return particles_.fixed[i] ? 0.0 : 1.0 / particles_.mass[i]; }

    std::string object_;
    OrientedParticles particles_;
    ShapeMatchingGroups groups_;
    SolverSettings settings_;
    std::vector<StretchConstraint> stretch_;
    std::vector<BendConstraint> bend_;
    // Pose at the start of the step, the predicted pose being projected, and the previous
    // step's change (for the second-order update).
    std::vector<Eigen::Vector3d> startPosition_, predicted_, lastStep_;
    std::vector<Eigen::Quaterniond> startOrientation_, predictedOrientation_;
    std::vector<Eigen::Vector3d> lastTurn_;
    std::vector<double> contactImpulse_; // per contact: normal correction so far in this step (kg m)
    std::vector<Eigen::Vector3d> contactPush_;     // per contact: normal and friction correction (kg m)
    std::vector<Eigen::Vector3d> contactImpulses_; // per contact: contactPush_ / dt summed over the step's substeps (N s)
    std::vector<double> contactGap_;     // per contact: distance after pre-stabilisation (m)
    std::vector<double> contactDistance_; // per contact, a later substep: found distance + own motion since (m)
    std::vector<Eigen::Vector3d> found_;  // positions when a step of several substeps found its contacts
    std::vector<Eigen::Vector3d> separation_; // per particle: separate()'s move (kept: no allocation per step)
    std::vector<int> touched_; // the particles of a substep's contacts (projectAllInRun)
    bool haveLastStep_ = false;
    double quietTime_ = 0.0;
};

} // namespace shatter::oriented
