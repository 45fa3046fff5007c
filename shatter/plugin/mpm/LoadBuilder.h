#pragma once
// Turns the scene's loads and fixed regions into per-particle forces and flags, once, in the
// reference configuration (the loaded particles are a material set: they keep their loads as
// the body deforms, i.e. dead loads).
//  - traction t (Pa) in a region: the part of each body's outline inside the region is cut
//    into pieces of at most h/4; each piece's force t·length goes to the nearest particle of
//    the outer layer. The total is exactly t times the loaded outline length.
//  - pressure p (Pa) in a region: the same, with the force −p·n·length for a piece with
//    outward normal n (positive pushes into the body, negative pulls).
//    Both may be limited to the outline facing one direction (Load::facing). A region that
//    catches outline facing different directions (a box around a plate's top edge that also
//    reaches down its sides: the sides then carry the traction as shear) gets a warning
//    naming the load and the loaded length per direction, unless `facing` is set.
//  - force F (N) in a region: shared by the particles inside in proportion to their mass,
//    so it accelerates them uniformly.
//  - fixed region: particles inside are held at rest (and the grid nodes they touch).
#include <shatter/plugin/mpm/ParticleSeeder.h>
#include <shatter/plugin/mpm/SimulationState.h>

#include <string>
#include <vector>

namespace shatter::mpm {

// Throws shatter::InputError naming loads[k] when a region loads nothing; appends to
// `warnings` one line per load whose region catches outline facing different directions.
std::vector<ParticleLoad> buildLoads(const Scene& scene, const SeededParticles& seeded,
                                     std::vector<std::string>& warnings);

// Throws shatter::InputError naming fixed[k] when a region holds no particle.
void markFixedParticles(const Scene& scene, Particles& particles);

// Sum of the loads' forces on each particle at `time`.
void applyLoads(const std::vector<ParticleLoad>& loads, double time, std::vector<Vec2>& force);

} // namespace shatter::mpm
