#pragma once
// Plastic deformation of a body that is rigid between impacts (source 000 §3.5): hit
// primitives are pushed in, the oriented-particle solver rearranges their neighbourhood
// with joint-box primitives fixed, and the result becomes the new rest shape.
#include <shatter/plugin/oriented/OrientedSolver.h>

#include <Eigen/Geometry>
#include <span>
#include <vector>

namespace shatter::oriented {

struct PlasticSettings {
    // Relative normal contact speed (m/s) above which a contact dents the body. Below it the
    // body stays rigid and unchanged.
    double threshold = 3.0;
    // The dent is this many graph rings around the hit primitives; the ring beyond is held.
    int rings = 3;
    // Shape-matching sweeps of the local rearrangement.
    int sweeps = 12;
    // Throws shatter::InputError naming `object` for a negative or non-finite threshold,
    // rings < 1 or sweeps < 1.
    void check(const std::string& body) const;
};

// A hit primitive and how far it is pushed (m, rest coordinates): the source's offset,
// relative normal speed × time step, along the contact normal into the body.
struct Dent {
    int particle = 0;
    Eigen::Vector3d offset = Eigen::Vector3d::Zero();
};

struct PlasticResult {
    std::vector<int> moved;                 // particles whose rest pose changed
    std::vector<Eigen::Isometry3d> motion;  // per moved particle: old rest -> new rest (rigid)
    double maxDisplacement = 0.0;           // m, largest rest-position change
};

// Applies dents to the solver's rest pose. The particles must be at their rest pose
// (position = restPosition, orientation = identity), as a rigid body's are. Particles
// marked fixed (joint boxes) never move. Afterwards positions equal the new rest positions,
// orientations are the identity again, rest moments are turned with their particles, and
// the groups' rest data are updated. Dents on the same particle: the longest offset wins.
// Throws shatter::InputError naming the object for an unknown particle or a non-finite offset.
PlasticResult deformPlastically(OrientedSolver& solver, std::span<const Dent> dents, const PlasticSettings& settings);

} // namespace shatter::oriented
