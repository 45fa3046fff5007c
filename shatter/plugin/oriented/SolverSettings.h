#pragma once
// Settings of the oriented-particle solver (source 000 §3.2.2). Units SI.
#include <Eigen/Core>
#include <shatter/plugin/oriented/SimdLanes.h>
#include <string>

namespace shatter::oriented {

// The largest SolverSettings::chebyshevRadius that check() takes at any sweep count.
inline constexpr double kMaxChebyshevRadius = 0.9;

// The divergence bound of SolverSettings::chebyshevRadius: the largest ρ that cannot make a step
// of `iterations` sweeps unstable. A step of n accelerated
// sweeps scales a mode of the sweeps' error e (plain sweep: e → λe) by Chebyshev's
// p_n(λ) = T_n(λ/ρ)/T_n(1/ρ), which swings down to −1/T_n(1/ρ) for λ in [−ρ, ρ]: the step
// overshoots the constraint. With PBD's v = Δx/Δt, a mode whose step scales its error by c
// evolves by μ² − 2cμ + c = 0, unstable for c < −1/3: T_n(1/ρ) > 3 is needed. With a
// margin, T_n(1/ρ) >= 4: ρ <= 1/cosh(acosh(4)/n), 0.632 at 2 sweeps, 0.802 at 3, 0.880 at 4,
// above 0.9 from 5 (measured on the 4,900-quad sheet unguarded: 2 sweeps held at 0.6 and blew
// up at 0.7, where T_2 = 3.08; 3 sweeps held at 0.8 and blew up at 0.9). 0 for 1 sweep (one
// sweep is never extrapolated).
double stableChebyshevRadius(int iterations);

// The largest ρ check() takes at `iterations` sweeps: stableChebyshevRadius, at most
// kMaxChebyshevRadius (one sweep is never extrapolated: any ρ up to that does nothing).
double maxChebyshevRadius(int iterations);

struct SolverSettings {
    int iterations = 4;          // constraint projection sweeps per step
    int rotationIterations = 2;  // warm-started rotation-extraction steps per group projection
    double stiffness = 1.0;      // shape-matching stiffness in [0, 1]; 1 = rigid goal each sweep
    // Chebyshev acceleration of a step's shape-matching sweeps (Wang 2015, "A Chebyshev
    // semi-iterative approach for accelerating projective and position-based dynamics"): ρ, an
    // estimate of the sweeps' spectral radius, in [0, 0.9]; 0 = off (plain sweeps). Sweep s's
    // own shape-matching motion δ_s becomes Δ_s = ω_s δ_s + (ω_s − 1) Δ_{s−1}, with ω_1 = 1,
    // ω_2 = 2/(2 − ρ²), ω_{s+1} = 4/(4 − ρ² ω_s): the slow, long-range modes (a hanging
    // sheet's stretch) converge in fewer sweeps. Σ m Δx stays 0 (contacts and pair constraints
    // are not extrapolated, orientations neither). At 0.65 the 4,900-quad sheet at 3 sweeps of
    // 0.33 drapes as at 4 plain sweeps of 0.3 (shatter-bench-oriented's sheet).
    // check() takes ρ up to maxChebyshevRadius(iterations) and rejects more (an error naming
    // the body, not a silent cap), so no ρ it takes explodes. Beyond that bound the sheet blew
    // up at ρ 0.9 with 3 sweeps (0.8 held) and at 0.7 with 2 sweeps of 0.51 (0.6 held): see
    // stableChebyshevRadius for why.
    double chebyshevRadius = 0.0;
    // Velocity damping in 1/s: v and ω are scaled by exp(−damping·Δt) each step. PBD with a
    // first-order velocity update already loses energy; 0 adds nothing.
    double damping = 0.0;
    // Angle (rad) and angle-per-step thresholds of the source: a spin with |ω|Δt below it is
    // not integrated, and an orientation change below it gives ω = 0 (no creeping).
    double epsilon = 1e-6;
    // Second-order (BDF2) velocity update, v = (3x_{n+1} − 4x_n + x_{n−1}) / 2Δt, which loses
    // less energy than (x_{n+1} − x_n)/Δt (source 000 §2.1, [3]).
    bool secondOrderVelocity = false;
    // Soft bodies: unconnected primitives of the body collide with each other (SelfContacts.h).
    bool selfContact = true;
    // Sleeping (soft bodies in a world): a body all of whose particles have moved slower than
    // sleepSpeed (m/s; translation and spin together, see OrientedSolver::quietTime) for
    // sleepTime (s) stops being stepped until something moving touches it. 0 = never sleeps.
    double sleepSpeed = 0.0;
    double sleepTime = 0.5;
    // Soft bodies in a world: while no moving body (dynamic, kinematic or another soft body)
    // is within reach, the body's contacts are found once every this many world substeps
    // (fewer while its own particles would move further than its contact slack, or half its
    // thinnest primitive, in that time), and Bullet skips its pairs with static bodies in the
    // substeps between (DeformationSystem). The solver still takes every substep, with the
    // contacts found last (OrientedSolver::step's substeps), so the material is the same as
    // at 1; what is saved is the collision work. Except when a dynamic body or a moving
    // surface is among the contacts found after skipped substeps (met late): it then takes one
    // step over the gathered time, which is softer (README, Fewer contact queries).
    // 1 = contacts every substep.
    int substepsPerStep = 1;
    Eigen::Vector3d gravity = Eigen::Vector3d(0, 0, -9.81); // m/s²
    // The instruction set of the projection sweeps and their rotation fits (SimdLanes.h): the
    // same bits on every path, so only the time differs; the fastest this processor runs.
    SimdPath simdPath = fastestSimdPath();

    // Throws shatter::InputError naming `object` when a value is out of range
    // (stiffness outside [0, 1], Chebyshev radius outside [0, maxChebyshevRadius(iterations)], iterations or substeps per step < 1, negative damping, epsilon or sleep
    // setting, non-finite, a SIMD path this processor lacks).
    void check(const std::string& body) const;
};

} // namespace shatter::oriented
