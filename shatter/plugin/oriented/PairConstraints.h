#pragma once
// Regular position-based-dynamics constraints between two particles (source 000 §3.2.3), for
// an artist who wants stretching and bending controlled apart from shape matching.
#include <shatter/plugin/oriented/OrientedParticles.h>

#include <span>

namespace shatter::oriented {

// Keeps the distance between two particle centres at its rest value. Mass-weighted, so
// Σ m Δx = 0 (linear momentum is kept).
struct StretchConstraint {
    int a = 0, b = 0;
    double restLength = 0.0; // m
    double stiffness = 1.0;  // fraction of the violation removed per projection, [0, 1]
    void project(const OrientedParticles& particles, std::span<Eigen::Vector3d> x) const;
};

// Keeps the relative orientation of two particles at its rest value (the identity: rest
// orientations are the identity), turning both about the shortest arc, weighted by the
// particles' rotational inertia about that axis.
struct BendConstraint {
    int a = 0, b = 0;
    double stiffness = 1.0; // [0, 1]
    void project(const OrientedParticles& particles, std::span<Eigen::Quaterniond> q) const;
};

} // namespace shatter::oriented
