#include "plugin/mpm/validation/InclinedCrack.h"

#include "plugin/mpm/HoopStress.h"
#include "plugin/mpm/Solver2D.h"
#include "plugin/mpm/validation/TensionPlate.h"

#include <cmath>
#include <numbers>

namespace shatter::mpm::validation {

namespace {

constexpr double kDx = kPlateDx;

double angleBetween(const Vec2& from, const Vec2& to) {
    return std::atan2(from.x() * to.y() - from.y() * to.x(), from.dot(to));
}

} // namespace

Scene inclinedCrackScene(const InclinedCrackCase& c) {
    const double h = kDx / c.ppc, a = c.aOverDx * kDx;
    const double width = std::round(c.widthOverA * a / (2 * h)) * 2 * h, height = 2 * width;
    Scene s = tensionPlate("inclined crack", width, height, c.sigma, c.ppc, c.kernel, c.maxTransits);
    s.materials[0].Kc = 1; // far below any K here: growth waits until setCrackPropagation()
    // A 45° line through the plate's centre would run through a diagonal of particle
    // centres; a quarter spacing off it, every particle is clearly on one side.
    const Vec2 d = Vec2(1, 1).normalized() * a;
    const Vec2 centre = Vec2(0.5 * width, 0.5 * height) + 0.25 * h * leftNormal(d.normalized());
    s.cracks.push_back(CrackSpec{{centre - d, centre + d}, false, TipSelection::Both, {}});
    return s;
}

InclinedCrackResult runInclinedCrack(const InclinedCrackCase& c) {
    const Scene scene = inclinedCrackScene(c);
    Solver2D solver(scene);
    if (c.threads > 0) solver.setThreads(c.threads);
    InclinedCrackResult r;
    const double a = c.aOverDx * kDx;
    r.KIreference = r.KIIreference = 0.5 * c.sigma * std::sqrt(std::numbers::pi * a);
    r.particles = long(solver.particles().size());
    const double transit = plateTransit(std::get<RectShape>(scene.bodies[0].shape.variant()).max.y());
    double previous = 0;
    for (int k = 1; k <= c.maxTransits; ++k) {
        solver.advance(transit);
        const auto tips = solver.tips();
        r.valid = tips.size() == 2 && tips[0].valid && tips[1].valid;
        if (!r.valid) return r;
        for (int t = 0; t < 2; ++t) {
            r.KI[t] = tips[size_t(t)].KI;
            r.KII[t] = tips[size_t(t)].KII;
            r.predictedKink[t] = kinkAngle(r.KI[t], r.KII[t]);
        }
        const double mean = 0.5 * (r.KI[0] + r.KI[1]);
        if (k >= 3 && std::abs(mean - previous) < 1e-3 * std::abs(mean)) {
            r.converged = true;
            break;
        }
        previous = mean;
    }
    // One substep with growth on: each tip grows once, in the direction of its filtered K.
    const Vec2 before[2] = {solver.cracks()[0].tipDirection(0), solver.cracks()[0].tipDirection(1)};
    const size_t points = solver.cracks()[0].points.size();
    solver.setCrackPropagation(0, true);
    solver.step(1.0);
    const Crack& crack = solver.cracks()[0];
    const size_t added = crack.points.size() - points;
    for (int t = 0; t < 2; ++t) {
        r.grew[t] = added > 0 && crack.tips[size_t(t)].result.grew > 0;
        if (r.grew[t]) r.kink[t] = angleBetween(before[t], crack.tipDirection(t));
    }
    r.substeps = solver.substeps();
    return r;
}

} // namespace shatter::mpm::validation
