#pragma once
// What a scene will cost, estimated from the scene alone before anything is allocated or
// simulated, and the limits it must stay within. A scene whose particle count, memory or
// substep count is beyond a limit is an error that gives the estimate and the option that
// raises the limit, so that no input runs for hours or exhausts memory without a word.
#include <shatter/plugin/mpm/Scene.h>

namespace shatter::mpm {

struct SceneLimits {
    // The defaults allow every shipped scene and validation with a margin. One substep costs
    // about 0.2 µs per particle on one core (640,000 particles: 83 substeps in 10 s), so at the
    // particle limit a substep takes about a second and progress still shows.
    double maxParticles = 4e6;  // particles, and crack points (shatter-mpm --max-particles)
    double maxSubsteps = 1e6;   // time.end / the CFL step at the start (--max-substeps)
    double maxMemory = 4e9;     // bytes, estimated (--max-memory, given in GB)
    // particles × substeps, the run's work: about 6 hours on one core at
    // kSecondsPerParticleStep (--max-particle-steps). Both limits above at once would be days.
    double maxParticleSteps = 1e11;
};

struct SceneEstimate {
    double particles = 0;    // Σ body area / spacing² (overlaps counted twice: an upper bound)
    double latticeSites = 0; // Σ lattice sites in the bodies' bounding boxes, tested when seeding
    double gridNodes = 0;    // nodes over the bodies' bounding box with the grid's padding
    double crackPoints = 0;  // points of the cracks once cut into growth steps
    double memory = 0;       // bytes
    double firstStep = 0;    // s, the CFL step at rest with the bodies' initial speeds
    double substeps = 0;     // time.end / firstStep (the step shrinks as things speed up)
    double frames = 0;       // time.end / time.frame
};

// Needs a scene that passed checkScene (finite, positive sizes).
SceneEstimate estimateScene(const Scene& scene);

// Throws shatter::InputError naming the scene, the estimate, the limit and the option.
void checkSceneLimits(const Scene& scene, const SceneEstimate& estimate, const SceneLimits& limits);

// Calibration of the memory estimate. Peak RSS of shatter-mpm --frames 1 --png-every 0 on a
// 20 m x 20 m PMMA square: 53 MB at 160,000 particles (dx 0.1 m), 193 MB at 640,000 (dx 0.05),
// with or without a crack: 290 bytes per particle. A node is a 32-byte field plus flags, three
// fields and crack data (about 200 bytes) with cracks; a crack point holds three positions.
constexpr double kBytesPerParticle = 300;
constexpr double kBytesPerGridNode = 64; // per field
constexpr double kBytesPerCrackPoint = 100;
// One particle's share of a substep on one core (SceneLimits' calibration above), for the
// time a run of many particle-steps would take.
constexpr double kSecondsPerParticleStep = 0.2e-6;

} // namespace shatter::mpm
