#include <shatter/plugin/mpm/Solver2D.h>

#include <shatter/plugin/mpm/CrackAdvection.h>
#include <shatter/plugin/mpm/CrackContact.h>
#include <shatter/plugin/mpm/CrackGrowth.h>
#include <shatter/plugin/mpm/CrackParticleSplit.h>
#include <shatter/plugin/mpm/CrackSetup.h>
#include <shatter/plugin/mpm/GridToParticle.h>
#include <shatter/plugin/mpm/GridUpdate.h>
#include <shatter/plugin/mpm/LoadBuilder.h>
#include <shatter/plugin/mpm/ParticleSeeder.h>
#include <shatter/plugin/mpm/ParticleToGrid.h>
#include <shatter/plugin/mpm/SceneCheck.h>
#include <shatter/plugin/mpm/TimeStep.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#ifdef _OPENMP
#include <omp.h>
#endif

namespace shatter::mpm {

Solver2D::Solver2D(const Scene& scene, const SceneLimits& limits) {
    checkScene(scene);
    checkSceneLimits(scene, estimateScene(scene), limits);
    state_.scene = scene;
    for (const Material& m : scene.materials) state_.models.push_back(ModelConstants::of(m, scene.analysis));
    SeededParticles seeded = seedParticles(scene);
    state_.spacing = seeded.spacing;
    state_.loads = buildLoads(scene, seeded, state_.warnings);
    state_.particles = std::move(seeded.particles);
    state_.cracks = buildCracks(scene);
    splitParticlesAtCracks(state_.cracks, seeded.spacing, state_.particles);
    markFixedParticles(scene, state_.particles);
#ifdef _OPENMP
    setThreads(omp_get_max_threads());
#endif
    updateAfterParticleEdit(state_);
}

Particles& Solver2D::mutableParticles() {
    derivedStale_ = true;
    return state_.particles;
}

void Solver2D::addCollider(std::shared_ptr<const Collider> collider) {
    state_.scene.colliders.push_back(std::move(collider));
}

void Solver2D::setThreads(int threads, bool adaptive) {
    threadControl_.configure(threads, adaptive);
    state_.threads = threadControl_.threads();
}

void Solver2D::setCrackPropagation(int crack, bool propagate) {
    for (CrackTip& t : state_.cracks.at(size_t(crack)).tips) t.propagates = propagate && t.active;
}

double Solver2D::stableTimeStep() {
    refreshIfEdited();
    return shatter::mpm::stableTimeStep(state_);
}

void Solver2D::refreshIfEdited() {
    if (!derivedStale_) return;
    updateAfterParticleEdit(state_);
    derivedStale_ = false;
}

double Solver2D::step(double maxStep) {
    const double dt = std::min(maxStep, stableTimeStep());
    takeStep(dt);
    return dt;
}

void Solver2D::takeStep(double dt) {
    refreshIfEdited();
    SimulationState& s = state_;
    s.threads = threadControl_.threads();
    const auto start = std::chrono::steady_clock::now();
    PhaseTimes::Clock clock(phaseTimes_);
    if (!s.loads.empty()) applyLoads(s.loads, s.time, s.externalForce); // else it stays zero
    s.segments.rebuild(s.cracks, crackEndGap(s));
    prepareGrid(s);
    clock.mark(PhaseTimes::Setup);
    s.fields.compute(s.particles.x, s.grid, s.segments, s.scene.grid.kernel, s.stripes, s.threads);
    clock.mark(PhaseTimes::Fields);
    particlesToGrid(s, dt);
    clock.mark(PhaseTimes::Scatter);
    updateGrid(s, dt); // velocities, crack contact, collisions, crack contact
    clock.mark(PhaseTimes::GridUpdate);
    gridToParticles(s, dt);
    clock.mark(PhaseTimes::Gather);
    advectCracks(s, dt);
    clock.mark(PhaseTimes::CrackAdvect);
    s.time += dt;
    ++s.substeps;
    if (s.hasCracks()) growCracks(s, dt);
    clock.mark(PhaseTimes::TipAnalysis);
    threadControl_.record(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
}

void Solver2D::advance(double duration, const std::function<void()>& afterSubstep) {
    for (Crack& c : state_.cracks)
        for (CrackTip& t : c.tips) t.result.grew = 0;
    const double end = state_.time + duration;
    while (state_.time < end) {
        const double remaining = end - state_.time;
        // Land exactly on `end`: a step that would leave a sliver is split in two.
        const double stable = stableTimeStep();
        const double dt = remaining <= stable ? remaining : std::min(stable, 0.5 * remaining);
        takeStep(dt);
        if (remaining <= stable) state_.time = end;
        if (afterSubstep) afterSubstep();
    }
    analyseTips();
}

void Solver2D::analyseTips() {
    refreshIfEdited();
    if (state_.hasCracks()) analyseAllTips(state_);
}

std::vector<TipResult> Solver2D::tips() const {
    std::vector<TipResult> out;
    for (const Crack& c : state_.cracks)
        for (const CrackTip& t : c.tips)
            if (t.active) out.push_back(t.result);
    return out;
}

Mat2 Solver2D::cauchyStress(size_t p) const {
    const Particles& P = state_.particles;
    const Mat2 tau = kirchhoffStress(state_.models[P.material[p]], P.Fe[p], P.Fp[p].determinant());
    return tau / (P.Fe[p] * P.Fp[p]).determinant();
}

double Solver2D::energyDensity(size_t p) const {
    const Particles& P = state_.particles;
    return shatter::mpm::energyDensity(state_.models[P.material[p]], P.Fe[p], P.Fp[p].determinant());
}

} // namespace shatter::mpm
