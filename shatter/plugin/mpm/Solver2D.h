#pragma once
// The 2D MPM crack solver (CRAMP with J-integral crack growth), the sidecar of Shatter:
//
//   shatter::mpm::Scene scene = shatter::mpm::loadScene("pull_test.json");
//   shatter::mpm::Solver2D solver(scene);
//   while (solver.time() < end) solver.advance(frameDt); // substeps from the CFL condition
//   for (const auto& tip : solver.tips()) { tip.J, tip.KI, tip.KII, tip.theta; }
//
// One substep follows the source's order (§3.1 of 001): particles to grid, grid velocity
// update, crack-surface contact, collisions, crack-surface contact, deformation gradient
// update and particle advection, crack particle advection, then J-integral and crack growth
// (once per half cell of wave travel: CrackGrowthSettings::analysisCells).
#include <shatter/plugin/mpm/AdaptiveThreads.h>
#include <shatter/plugin/mpm/Crack.h>
#include <shatter/plugin/mpm/Particles.h>
#include <shatter/plugin/mpm/PhaseTimes.h>
#include <shatter/plugin/mpm/Scene.h>
#include <shatter/plugin/mpm/SceneBudget.h>
#include <shatter/plugin/mpm/SimulationState.h>

#include <functional>
#include <memory>
#include <vector>

namespace shatter::mpm {

class Solver2D {
public:
    // Checks the scene (shatter::InputError naming the key on a violation) and its estimated
    // cost against `limits` (SceneBudget.h) before seeding it.
    explicit Solver2D(const Scene& scene, const SceneLimits& limits = {});

    // Adds an obstacle, e.g. a Bullet collision object seen through its signed distance.
    void addCollider(std::shared_ptr<const Collider> collider);
    // Threads for the particle and grid loops (default: OpenMP's, i.e. all cores). Results
    // do not depend on it. `adaptive` (the default): at most `threads`, fewer while they are
    // measured to be slower (another process busy on the machine; AdaptiveThreads.h).
    void setThreads(int threads, bool adaptive = true);
    // The maximum set; threadsInUse(): what the last substep used.
    int threads() const { return threadControl_.maximum(); }
    int threadsInUse() const { return state_.threads; }

    // Switches growth of crack `crack`'s active tips on or off (e.g. after a settling phase).
    void setCrackPropagation(int crack, bool propagate);

    // Advances by `duration` seconds in substeps of at most the stable step; the last
    // substep is shortened to land exactly. Tip results are refreshed at the end.
    // `afterSubstep`, when given, is called after every substep (a program's progress line).
    void advance(double duration, const std::function<void()>& afterSubstep = {});
    // One substep of at most `maxStep` seconds; returns the step taken.
    double step(double maxStep);
    // Runs the J-integral at every active tip (growth is decided only inside step()).
    void analyseTips();

    double time() const { return state_.time; }
    long substeps() const { return state_.substeps; }
    // The CFL step for the current state.
    double stableTimeStep();
    // J, K_I, K_II, kink angle and growth count of every active tip, crack by crack.
    std::vector<TipResult> tips() const;

    const Scene& scene() const { return state_.scene; }
    const Particles& particles() const { return state_.particles; }
    // For setting up initial conditions (velocities, deformation) in code; the next
    // substep recomputes the stable step and the stresses from what was written.
    Particles& mutableParticles();
    const std::vector<Crack>& cracks() const { return state_.cracks; }
    double particleSpacing() const { return state_.spacing; }
    // Cauchy stress of particle p from its current deformation.
    Mat2 cauchyStress(size_t p) const;
    // Stored elastic energy density of particle p, J/m³ (per reference volume).
    double energyDensity(size_t p) const;
    const SimulationState& state() const { return state_; }
    // What the scene probably did not mean, found while setting it up (e.g. a load region
    // that catches outline facing different directions); one line each, naming the key.
    const std::vector<std::string>& warnings() const { return state_.warnings; }

    // Wall time per stage of all substeps so far (a benchmark's breakdown).
    const PhaseTimes& phaseTimes() const { return phaseTimes_; }

private:
    void takeStep(double dt);
    // After mutableParticles(): the stresses and the fastest signal follow the edit.
    void refreshIfEdited();

    SimulationState state_;
    AdaptiveThreads threadControl_;
    PhaseTimes phaseTimes_;
    bool derivedStale_ = false;
};

} // namespace shatter::mpm
