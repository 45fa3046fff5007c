#include <shatter/plugin/mpm/validation/InclinedCrack.h>

#include <shatter/plugin/mpm/HoopStress.h>
#include <shatter/plugin/mpm/Solver2D.h>
#include <shatter/plugin/mpm/WestergaardField.h>
#include <shatter/plugin/mpm/validation/TensionPlate.h>

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
    const double side = std::round(c.widthOverA * a / (2 * h)) * 2 * h;
    Scene s = tensionPlate("inclined crack", side, side, c.sigma, c.ppc, c.kernel, c.maxTransits);
    s.materials[0].Kc = 1; // far below any K here: growth waits until setCrackPropagation()
    // A 45° line through the plate's centre would run through a diagonal of particle
    // centres; a quarter spacing off it, every particle is clearly on one side.
    const Vec2 t = Vec2(1, 1).normalized(), n = leftNormal(t);
    const Vec2 centre = Vec2(0.5 * side, 0.5 * side) + 0.25 * h * n + c.shiftCells * kDx * t;
    s.cracks.push_back(CrackSpec{{centre - a * t, centre + a * t}, false, TipSelection::Both, {}});
    // The exact tractions, one load per particle spacing of the outline, ramped like the
    // plate's own loads (TensionPlate.h).
    WestergaardField field;
    field.a = a;
    field.sigma = field.tau = 0.5 * c.sigma;
    field.E = s.materials[0].E;
    field.nu = s.materials[0].nu;
    field.analysis = s.analysis;
    const double ramp = s.loads.front().ramp, band = 0.01 * kDx;
    s.loads.clear();
    const int pieces = int(std::round(side / h));
    for (int e = 0; e < 4; ++e)
        for (int k = 0; k < pieces; ++k) {
            const double u0 = k * h, u1 = (k + 1) * h, um = (k + 0.5) * h;
            // edges: bottom (y = 0), right (x = side), top (y = side), left (x = 0)
            const Vec2 normal = e == 0 ? Vec2(0, -1) : e == 1 ? Vec2(1, 0) : e == 2 ? Vec2(0, 1) : Vec2(-1, 0);
            const Vec2 mid = e == 0 ? Vec2(um, 0) : e == 1 ? Vec2(side, um) : e == 2 ? Vec2(um, side) : Vec2(0, um);
            const Box region = e % 2 == 0 ? Box{Vec2(u0, mid.y() - band), Vec2(u1, mid.y() + band)}
                                          : Box{Vec2(mid.x() - band, u0), Vec2(mid.x() + band, u1)};
            const Vec2 local(t.dot(mid - centre), n.dot(mid - centre));
            Mat2 R;
            R.col(0) = t;
            R.col(1) = n;
            const Mat2 stress = R * field.at(local.x(), local.y()).stress * R.transpose();
            s.loads.push_back(Load{region, Load::Kind::Traction, stress * normal, ramp});
        }
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
