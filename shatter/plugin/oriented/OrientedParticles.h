#pragma once
// The state of an oriented-particle body (source 000 §3.2): one particle per convex
// primitive, with position, orientation, velocity, spin, mass and rest pose.
#include <shatter/plugin/geometry/ConvexPolyhedron.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>
#include <vector>

namespace shatter::oriented {

// Structure of arrays, one entry per particle. Positions are the particles' centres of
// mass. Rest orientation is the identity for every particle: a primitive's rest geometry
// is stored in rest coordinates, and `orientation` turns it into the current pose.
struct OrientedParticles {
    std::vector<Eigen::Vector3d> position;
    std::vector<Eigen::Quaterniond> orientation;
    std::vector<Eigen::Vector3d> velocity;        // m/s
    std::vector<Eigen::Vector3d> angularVelocity; // rad/s
    std::vector<double> mass;                     // kg
    std::vector<bool> fixed;                      // held in place (joint boxes, boundary conditions)
    std::vector<Eigen::Vector3d> restPosition;    // centre of mass in rest coordinates
    std::vector<Eigen::Matrix3d> restMoment;      // C_i = ∫ρ r rᵀ dV in rest axes (ParticleMoment.h)

    int size() const { return int(position.size()); }
    // Appends a particle at rest (zero velocities, identity orientation).
    void add(const Eigen::Vector3d& restCentre, double particleMass, const Eigen::Matrix3d& moment);
    // Moment A_i = R_i C_i of particle i at orientation q.
    // Inline: the group projection calls it once per group and sweep.
    Eigen::Matrix3d moment(int i, const Eigen::Quaterniond& q) const { return q.toRotationMatrix() * restMoment[i]; }
    // Σ m v and Σ (m x × v + I ω) about the origin, I = R (tr C 𝟙 − C) Rᵀ.
    Eigen::Vector3d linearMomentum() const;
    Eigen::Vector3d angularMomentum() const;
    double kineticEnergy() const;
    // How far the body is from a rigid motion of its rest shape: the largest change of a
    // centre-to-centre distance from its rest value (m). O(n²): for tests and summaries.
    double restShapeError() const;
};

// One particle per primitive at its centre of mass, with the primitive's exact mass and
// moment for `density` (kg/m³). Throws shatter::InputError naming `object` and the
// primitive when a primitive has zero (or non-finite) mass.
OrientedParticles particlesFromPrimitives(const std::vector<geometry::ConvexPolyhedron>& primitives, double density,
                                          const std::string& object);

} // namespace shatter::oriented
