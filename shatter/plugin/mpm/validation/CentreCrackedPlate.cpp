#include <shatter/plugin/mpm/validation/CentreCrackedPlate.h>

#include <shatter/plugin/mpm/Solver2D.h>
#include <shatter/plugin/mpm/validation/TensionPlate.h>

#include <algorithm>
#include <utility>
#include <cmath>
#include <numbers>

namespace shatter::mpm::validation {

namespace {

constexpr double kDx = kPlateDx;

// The smallest whole number of cells a >= aOverDx for which W = 2a/λ is an even number of
// cells: the crack then lies on a grid line and its tips on grid lines, symmetric about
// the plate's centre line. A discrete crack ends at a grid node (see CentreCrackedPlate.h).
std::pair<double, double> alignedGeometry(double lambda, double aOverDx) {
    for (int a = int(std::ceil(aOverDx - 1e-9)); a < int(std::ceil(aOverDx)) + 200; ++a) {
        const double w = 2 * a / lambda;
        if (std::abs(w - 2 * std::round(w / 2)) < 1e-9) return {a * kDx, w * kDx};
    }
    const double w = 2 * std::ceil(aOverDx / lambda - 1e-9); // fallback: symmetric, tips off the grid
    return {0.5 * lambda * w * kDx, w * kDx};
}

} // namespace

double tadaCentreCrack(double lambda) {
    const double l2 = lambda * lambda;
    return (1 - 0.025 * l2 + 0.06 * l2 * l2) * std::sqrt(1 / std::cos(std::numbers::pi * lambda / 2));
}

double CentreCrackedPlateResult::error() const {
    return std::max(std::abs(KIstart / KIreference - 1), std::abs(KIend / KIreference - 1));
}

Scene centreCrackedPlateScene(const CentreCrackedPlateCase& c) {
    const auto [a, width] = c.widthCells > 0 ? std::pair(c.aOverDx * kDx, c.widthCells * kDx)
                                             : alignedGeometry(c.lambda, c.aOverDx);
    const double height = 2 * width;
    Scene s = tensionPlate("centre-cracked plate", width, height, c.sigma, c.ppc, c.kernel, c.maxTransits);
    s.analysis = c.analysis;
    const double y = 0.5 * height + c.lineOffset * kDx;
    s.cracks.push_back(CrackSpec{{Vec2(0.5 * width - a, y), Vec2(0.5 * width + a, y)}, false, TipSelection::Both, {}});
    return s;
}

CentreCrackFiniteElementCase finiteElementCase(const CentreCrackedPlateCase& c) {
    const Scene scene = centreCrackedPlateScene(c);
    const auto& rect = std::get<RectShape>(scene.bodies[0].shape.variant());
    const auto& crack = scene.cracks[0].points;
    CentreCrackFiniteElementCase fe;
    fe.width = rect.max.x() - rect.min.x();
    fe.height = rect.max.y() - rect.min.y();
    fe.a = 0.5 * (crack[1] - crack[0]).norm();
    fe.sigma = c.sigma;
    fe.analysis = c.analysis;
    fe.E = scene.materials[0].E;
    fe.nu = scene.materials[0].nu;
    return fe;
}

CentreCrackedPlateResult runCentreCrackedPlate(const CentreCrackedPlateCase& c) {
    const Scene scene = centreCrackedPlateScene(c);
    Solver2D solver(scene);
    if (c.threads > 0) solver.setThreads(c.threads);
    const auto& crack = scene.cracks[0].points;
    const double a = 0.5 * (crack[1] - crack[0]).norm();
    const auto& rect = std::get<RectShape>(scene.bodies[0].shape.variant());
    CentreCrackedPlateResult r;
    r.lambda = 2 * a / (rect.max.x() - rect.min.x());
    r.aOverDx = a / scene.grid.dx;
    r.KIreference = tadaCentreCrack(r.lambda) * c.sigma * std::sqrt(std::numbers::pi * a);
    r.particles = long(solver.particles().size());
    const double transit = plateTransit(rect.max.y() - rect.min.y());
    double previous = 0;
    for (int k = 1; k <= c.maxTransits; ++k) {
        solver.advance(transit);
        const auto tips = solver.tips();
        r.valid = tips.size() == 2 && tips[0].valid && tips[1].valid;
        if (!r.valid) break;
        r.KIstart = tips[0].KI;
        r.KIend = tips[1].KI;
        r.KIIstart = tips[0].KII;
        r.KIIend = tips[1].KII;
        r.mixityHistory.push_back(std::max(std::abs(r.KIIstart / r.KIstart), std::abs(r.KIIend / r.KIend)));
        const double mean = 0.5 * (r.KIstart + r.KIend);
        // After the ramp (one transit), settled when a transit changes K_I by < 0.1%.
        if (k >= 3 && std::abs(mean - previous) < 1e-3 * std::abs(mean)) {
            r.converged = true;
            break;
        }
        previous = mean;
    }
    r.time = solver.time();
    r.substeps = solver.substeps();
    return r;
}

} // namespace shatter::mpm::validation
