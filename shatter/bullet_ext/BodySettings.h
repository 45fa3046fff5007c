#pragma once
#include <shatter/plugin/geometry/PhysicalMesh.h>
#include <shatter/plugin/oriented/PlasticDeformation.h>
#include <shatter/plugin/oriented/SolverSettings.h>

namespace shatter {

// How a body's shape may change (source 000 §3.2-3.5).
enum class Deformation {
    None,    // a rigid body for ever
    Plastic, // rigid until a contact's normal speed exceeds plastic.threshold, then dented
    Soft,    // oriented particles every step: wobbles and recovers (kinematic to other bodies)
};

// How a visual mesh becomes a Bullet body. Units SI; every default gives a plausible scene.
struct BodySettings {
    geometry::PhysicalMeshSettings mesh; // thickness (m), density (kg/m³), contact tolerance (m)
    double friction = 0.6;               // Coulomb coefficient (Bullet combines by product)
    double restitution = 0.0;            // 0 = no bounce
    // Rolling and spinning resistance as a lever arm in m (Bullet's rolling friction). Give
    // round bodies (a bowl, a wheel) about 0.001 so they stop rocking as real ones do; leave
    // flat and jointed bodies at 0, where Bullet's rolling friction makes them creep.
    double rollingFriction = 0.0;
    double spinningFriction = 0.0;
    double collisionMargin = 0.001;      // m, Bullet's margin around each primitive
    bool dynamic = true;                 // false: a static body (infinite mass)
    double jointBreakingImpulse = 0.0;   // N·s; 0 = joints from joint boxes never break
    double linearDamping = 0.0;          // 1/s
    double angularDamping = 0.0;         // 1/s
    Deformation deformation = Deformation::None;
    oriented::SolverSettings solver;     // oriented-particle solver (Soft and Plastic)
    oriented::PlasticSettings plastic;   // dent threshold and extent (Plastic)
};

} // namespace shatter
