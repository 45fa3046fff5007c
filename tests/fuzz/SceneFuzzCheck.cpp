#include "tests/fuzz/FuzzChecks.h"

#include <shatter/plugin/common/InputError.h>
#include <shatter/plugin/mpm/SceneBudget.h>
#include <shatter/plugin/mpm/SceneFile.h>
#include <shatter/plugin/mpm/Solver2D.h>

#include <cstdio>
#include <exception>

namespace shatter::test {

namespace {

// Small enough that one input runs in milliseconds (a fuzzer needs thousands a minute).
mpm::SceneLimits fuzzLimits() {
    mpm::SceneLimits limits;
    limits.maxParticles = 20'000;
    limits.maxMemory = 256e6;
    return limits;
}

bool finite(const mpm::Solver2D& solver) {
    const mpm::Particles& p = solver.particles();
    for (size_t i = 0; i < p.size(); ++i)
        if (!p.x[i].allFinite() || !p.v[i].allFinite()) return false;
    return true;
}

} // namespace

FuzzOutcome checkSceneInput(const std::string& bytes) {
    try {
        const mpm::Scene scene = mpm::parseScene(bytes, "fuzz.json");
        const mpm::SceneLimits limits = fuzzLimits();
        mpm::checkSceneLimits(scene, mpm::estimateScene(scene), limits);
        mpm::Solver2D solver(scene, limits);
        solver.setThreads(1);
        solver.step(scene.time.frame);
        return finite(solver) ? FuzzOutcome::Accepted : FuzzOutcome::Bug;
    } catch (const InputError&) {
        return FuzzOutcome::Refused;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "unexpected exception: %s\n", e.what());
        return FuzzOutcome::Bug;
    }
}

} // namespace shatter::test
