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

// A contact of a particle with something that does not move during the step, from the
// collision detection at the start of the step. A particle that starts inside is first
// moved out (no velocity is made of that); then n·(x − x_start) + distance ≥ 0 keeps it
// from crossing the surface, and Coulomb friction (coefficient `friction`) limits the
// tangential motion, static when it can be.
struct ParticleContact {
    int particle = 0;
    Eigen::Vector3d normal = Eigen::Vector3d::UnitZ(); // unit, from the other surface towards the particle
    double distance = 0.0;                             // m, signed separation (< 0: penetrating)
    double friction = 0.5;
};

class OrientedSolver {
public:
    // One shape-matching group per particle over `connections`. Throws shatter::InputError
    // naming `object` for bad settings or connections. A graph with several components
    // simulates each on its own (groups never cross components).
    OrientedSolver(std::string object, OrientedParticles particles,
                   const std::vector<std::pair<int, int>>& connections, const SolverSettings& settings);

    // Advances by dt (s): predict with gravity and velocities, project contacts, pair
    // constraints and shape matching `iterations` times, update velocities from the change
    // of position and orientation. Throws InputError naming the object for a contact with a
    // non-finite value or an unknown particle.
    void step(double dt, std::span<const ParticleContact> contacts = {});

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

    // Deformation matrix of particle i's group at the current pose (source 000 §3.3).
    Eigen::Matrix3d deformation(int i) const;

private:
    void separate(std::span<const ParticleContact> contacts);
    void predict(double dt);
    void projectContacts(std::span<const ParticleContact> contacts);
    void updateVelocities(double dt);
    void checkContacts(std::span<const ParticleContact> contacts) const;

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
    std::vector<double> contactPush_; // per contact: normal correction so far in this step (m)
    std::vector<double> contactGap_;  // per contact: distance after pre-stabilisation (m)
    bool haveLastStep_ = false;
};

} // namespace shatter::oriented
