#include <shatter/plugin/mpm/SceneBudget.h>

#include <shatter/plugin/common/InputError.h>
#include <shatter/plugin/mpm/ConstitutiveModel.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

namespace shatter::mpm {

namespace {

constexpr int kGridPadCells = 3; // ParticleToGrid.cpp's pad around the particles

double extentCells(double length, double cell) { return length / cell; }

double crackLength(const std::vector<Vec2>& points) {
    double length = 0;
    for (size_t k = 0; k + 1 < points.size(); ++k) length += (points[k + 1] - points[k]).norm();
    return length;
}

std::string number(double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%.3g", v);
    return text;
}

[[noreturn]] void fail(const Scene& scene, const std::string& what) {
    throw InputError((scene.source.empty() ? std::string() : scene.source + ": ") + what);
}

} // namespace

SceneEstimate estimateScene(const Scene& scene) {
    SceneEstimate e;
    const double dx = scene.grid.dx, h = dx / scene.grid.ppc;
    Box all{Vec2::Constant(INFINITY), Vec2::Constant(-INFINITY)};
    double fastest = 0;
    for (const Body& b : scene.bodies) {
        const Box box = b.shape.bounds();
        all.min = all.min.cwiseMin(box.min);
        all.max = all.max.cwiseMax(box.max);
        e.particles += b.shape.area() / (h * h);
        e.latticeSites += (extentCells(box.max.x() - box.min.x(), h) + 2) * (extentCells(box.max.y() - box.min.y(), h) + 2);
        const ModelConstants c = ModelConstants::of(scene.materials[size_t(b.material)], scene.analysis);
        fastest = std::max(fastest, c.waveSpeed0 + b.velocity.norm());
    }
    e.gridNodes = (extentCells(all.max.x() - all.min.x(), dx) + 1 + 2 * kGridPadCells) *
                  (extentCells(all.max.y() - all.min.y(), dx) + 1 + 2 * kGridPadCells);
    const double growth = scene.fracture.growthCells * dx;
    for (const CrackSpec& c : scene.cracks)
        e.crackPoints += crackLength(c.points) / growth + double(c.points.size()) + crackLength(c.guide) / growth +
                         double(c.guide.size());
    // Cracks bring two more velocity fields and their crack data at every node.
    const double nodeFactor = scene.cracks.empty() ? 1.0 : 3.0;
    e.memory = e.particles * kBytesPerParticle + e.gridNodes * kBytesPerGridNode * nodeFactor +
               e.crackPoints * kBytesPerCrackPoint;
    e.firstStep = std::min(fastest > 0 ? scene.time.cfl * dx / fastest : INFINITY, scene.time.maxStep);
    e.substeps = scene.time.end / e.firstStep;
    e.frames = scene.time.end / scene.time.frame;
    return e;
}

void checkSceneLimits(const Scene& scene, const SceneEstimate& e, const SceneLimits& limits) {
    const double h = scene.grid.dx / scene.grid.ppc;
    if (!(e.particles <= limits.maxParticles))
        fail(scene, "the bodies hold about " + number(e.particles) + " particles at spacing " + number(h) +
                        " m (grid.dx / grid.ppc), more than the limit of " + number(limits.maxParticles) +
                        " (raise it with --max-particles, or make grid.dx larger)");
    if (!(e.latticeSites <= 4 * limits.maxParticles))
        fail(scene, "seeding would test about " + number(e.latticeSites) + " lattice sites in the bodies' bounding boxes at spacing " +
                        number(h) + " m, more than 4 x the particle limit of " + number(limits.maxParticles) +
                        " (raise it with --max-particles, or make grid.dx larger)");
    if (!(e.crackPoints <= limits.maxParticles))
        fail(scene, "the cracks would be cut into about " + number(e.crackPoints) + " points (their length / (fracture.growth x grid.dx)), more than the limit of " +
                        number(limits.maxParticles) + " (raise it with --max-particles)");
    if (!(e.memory <= limits.maxMemory))
        fail(scene, "the scene needs about " + number(e.memory / 1e9) + " GB (" + number(e.particles) + " particles, " +
                        number(e.gridNodes) + " grid nodes), more than the limit of " + number(limits.maxMemory / 1e9) +
                        " GB (raise it with --max-memory)");
    if (!(e.frames <= limits.maxSubsteps))
        fail(scene, "time.end / time.frame is " + number(e.frames) + " frames, each at least one substep: more than the limit of " +
                        number(limits.maxSubsteps) + " substeps (raise it with --max-substeps, or make time.frame larger)");
    if (!(e.substeps <= limits.maxSubsteps))
        fail(scene, "a run of " + number(scene.time.end) + " s (time.end) in CFL steps of " + number(e.firstStep) + " s is about " +
                        number(e.substeps) + " substeps, more than the limit of " + number(limits.maxSubsteps) +
                        " (raise it with --max-substeps, or shorten time.end)");
    const double particleSteps = e.particles * e.substeps;
    if (!(particleSteps <= limits.maxParticleSteps))
        fail(scene, "about " + number(e.particles) + " particles for about " + number(e.substeps) + " substeps are " +
                        number(particleSteps) + " particle-steps, about " +
                        number(particleSteps * kSecondsPerParticleStep / 3600) +
                        " hours on one core: more than the limit of " + number(limits.maxParticleSteps) +
                        " (raise it with --max-particle-steps, make grid.dx larger or shorten time.end)");
}

} // namespace shatter::mpm
