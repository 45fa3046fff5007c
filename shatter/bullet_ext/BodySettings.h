#pragma once
// How a body of Shatter's behaves in the Bullet world. Units SI; every default gives a
// plausible scene. Every settings struct checks itself (check(body)), naming the body and field.
#include <shatter/bullet_ext/fracture/FractureSettings.h>
#include <shatter/bullet_ext/fracture/TearSettings.h>
#include <shatter/plugin/geometry/PhysicalMesh.h>
#include <shatter/plugin/oriented/PlasticDeformation.h>
#include <shatter/plugin/oriented/SolverSettings.h>

#include <BulletDynamics/Dynamics/btRigidBody.h>

#include <string>

namespace shatter {

// What Bullet needs of any rigid body Shatter makes: a visual body, each piece of a lattice
// body, each fragment. Shared by BodySettings and LatticeSettings.
struct RigidBodySettings {
    double friction = 0.6;    // Coulomb coefficient (Bullet combines by product)
    double restitution = 0.0; // 0 = no bounce
    // Rolling and spinning resistance as a lever arm in m (Bullet's rolling friction). Give
    // round bodies (a bowl, a wheel) about 0.001 so they stop rocking as real ones do; leave
    // flat and jointed bodies at 0, where Bullet's rolling friction makes them creep.
    double rollingFriction = 0.0;
    double spinningFriction = 0.0;
    double linearDamping = 0.0;     // 1/s
    double angularDamping = 0.0;    // 1/s
    double collisionMargin = 0.001; // m, Bullet's margin around each primitive

    // Every value must be >= 0 and finite.
    void check(const std::string& body) const;
    // Friction, restitution, rolling and spinning friction and damping into Bullet's
    // construction info (the margin goes on the shape).
    void applyTo(btRigidBody::btRigidBodyConstructionInfo& info) const;
};

// How a body may change its shape (source 000 §3.2-3.5).
enum class Deformation {
    None,    // a rigid body for ever
    Plastic, // rigid until a contact's normal speed exceeds plastic.threshold, then dented
    Soft,    // oriented particles every step: wobbles and recovers (kinematic to other bodies)
};

// How a physical mesh behaves as a Bullet body. (How a visual mesh becomes a physical mesh —
// units, scale, thickness, density — is geometry::PhysicalMeshSettings, given where the mesh
// is built: geometry::buildPhysicalObject or buildPhysicalMesh.)
struct BodySettings {
    RigidBodySettings rigidBody;
    bool dynamic = true;               // false: a static body (infinite mass)
    double jointBreakingImpulse = 0.0; // N·s; 0 = joints from joint boxes never break
    Deformation deformation = Deformation::None;
    oriented::SolverSettings solver;   // oriented-particle solver (Soft and Plastic)
    oriented::PlasticSettings plastic; // dent threshold and extent (Plastic)
    FractureSettings fracture;         // fracture where hit (off by default): Shatter needs Deformation::None,
                                       // Subdivide None or Plastic
    TearSettings tear;                 // tearing where stretched (off by default; Soft or Plastic only)

    // The rigid-body block, the joint breaking impulse, the fracture and tear settings when enabled,
    // and the solver and plastic settings of a deformable body.
    void check(const std::string& body) const;
};

} // namespace shatter
