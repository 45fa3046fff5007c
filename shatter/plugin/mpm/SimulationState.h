#pragma once
// Everything that changes during a 2D simulation, shared by the solver's stages.
#include <shatter/plugin/mpm/ConstitutiveModel.h>
#include <shatter/plugin/mpm/Crack.h>
#include <shatter/plugin/mpm/FieldAssignment.h>
#include <shatter/plugin/mpm/Grid.h>
#include <shatter/plugin/mpm/LineCrossing.h>
#include <shatter/plugin/mpm/Particles.h>
#include <shatter/plugin/mpm/Scene.h>
#include <shatter/plugin/mpm/StripeOrder.h>

#include <cstdint>
#include <string>
#include <vector>

namespace shatter::mpm {

// External force on particles from the scene's loads: per load, the particles it acts on
// and their share at full load.
struct ParticleLoad {
    std::vector<std::uint32_t> particle;
    std::vector<Vec2> force; // N (per metre of thickness)
    double ramp = 0;         // s

    double factor(double time) const { return ramp > 0 && time < ramp ? time / ramp : 1.0; }
};

struct SimulationState {
    Scene scene;
    std::vector<ModelConstants> models; // per material
    Particles particles;
    std::vector<Vec2> externalForce;    // per particle, this substep
    // Per particle: Kirchhoff stress τ of its current F_E, F_P (GridToParticle.h).
    std::vector<Mat2> stress;
    std::vector<ParticleLoad> loads;
    std::vector<std::string> warnings; // set up once (LoadBuilder.h); a program prints them
    Grid grid;
    StripeOrder stripes;
    std::vector<Crack> cracks;
    CrackSegments segments;
    FieldAssignment fields;
    double time = 0;
    long substeps = 0;
    // When the propagating tips were last analysed (CrackGrowthSettings::analysisCells).
    long lastTipAnalysisSubstep = -1;
    double lastTipAnalysisTime = 0;
    // max over particles of (wave speed + speed), m/s, as of the last particle update: what
    // the CFL condition of the next substep needs (TimeStep.h, GridToParticle.h).
    double fastestSignal = 0;
    Box particleBounds; // of the particle positions, as of the last particle update
    // Per chunk of 512 consecutive particles (GridToParticle.cpp), the box of their positions
    // as of the last particle update: which colliders the next gather tests per chunk.
    std::vector<Box> chunkBounds;
    int threads = 1;
    double spacing = 0; // particle spacing, m

    bool hasCracks() const { return !cracks.empty(); }
};

// How far from its ends a crack stops separating velocity fields (LineCrossing.h): half a
// cell, so that the discrete crack ends at the grid node nearest to its true end.
inline double crackEndGap(const SimulationState& s) { return 0.5 * s.scene.grid.dx; }

} // namespace shatter::mpm
