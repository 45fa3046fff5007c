#include <shatter/plugin/mpm/validation/ExactFieldCheck.h>

#include <shatter/plugin/mpm/Crack.h>
#include <shatter/plugin/mpm/CrackSetup.h>
#include <shatter/plugin/mpm/JIntegral.h>
#include <shatter/plugin/mpm/LineCrossing.h>
#include <shatter/plugin/mpm/StressIntensity.h>
#include <shatter/plugin/mpm/WestergaardField.h>

#include <cmath>

namespace shatter::mpm::validation {

namespace {

Mat2 rotation(double angle) {
    Mat2 R;
    R << std::cos(angle), -std::sin(angle), std::sin(angle), std::cos(angle);
    return R;
}

double linearEnergy(const Mat2& stress, const Mat2& gradU) {
    return 0.5 * (stress.array() * (0.5 * (gradU + gradU.transpose())).array()).sum();
}

} // namespace

ExactFieldResult runExactFieldCase(const ExactFieldCase& c) {
    WestergaardField field;
    field.a = c.a;
    field.sigma = c.sigma;
    field.tau = c.tau;
    field.E = c.E;
    field.nu = c.nu;
    field.analysis = c.analysis;
    const Mat2 R = rotation(c.angle);
    auto toWorld = [&](const Vec2& local) { return Vec2(c.centre + R * local); };

    // The crack: straight, resampled at half a cell like a scene crack, faces displaced by
    // the exact field (as the solver's surface tracking would report them).
    Crack crack;
    std::vector<Vec2> points{Vec2(-c.a, 0)};
    for (const Vec2& p : resamplePath({Vec2(-c.a, 0), Vec2(c.a, 0)}, 0.5 * c.dx)) points.push_back(p);
    for (const Vec2& p : points) {
        const bool tipPoint = std::abs(std::abs(p.x()) - c.a) < 1e-12 * c.a;
        const double tiny = 1e-12 * c.a;
        const Vec2 up = tipPoint ? Vec2::Zero() : Vec2(field.at(p.x(), tiny).u);
        const Vec2 down = tipPoint ? Vec2::Zero() : Vec2(field.at(p.x(), -tiny).u);
        crack.points.push_back(toWorld(p));
        // Offsets from the crack particle, which sits halfway (centre-of-mass motion).
        crack.above.push_back(R * (0.5 * (up - down)));
        crack.below.push_back(R * (0.5 * (down - up)));
    }
    CrackSegments segments;
    segments.rebuild({crack});

    // Particles on a lattice of spacing dx/2 around the tip, offset by half a spacing so
    // none sits on the crack line.
    const double h = 0.5 * c.dx, radius = 2 * c.dx, reach = radius + 3 * c.dx;
    const Vec2 tipLocal(c.tip == 1 ? c.a : -c.a, 0);
    std::vector<NearTipSample> samples;
    const int n = int(std::ceil(reach / h));
    for (int i = -n; i < n; ++i)
        for (int j = -n; j < n; ++j) {
            const Vec2 local = tipLocal + h * Vec2(i + 0.5, j + 0.5);
            const WestergaardField::State s = field.at(local.x(), local.y());
            NearTipSample q;
            q.x = toWorld(local);
            q.volume = h * h;
            q.mass = 1000 * q.volume;
            q.sigma = R * s.stress * R.transpose();
            q.gradU = R * s.gradU * R.transpose();
            q.W = linearEnergy(s.stress, s.gradU);
            samples.push_back(q);
        }
    const int tip = c.tip;
    Vec2 crossing;
    ExactFieldResult out;
    Material m;
    m.E = c.E;
    m.nu = c.nu;
    const double Eeff = m.effectiveModulus(c.analysis);
    out.KIref = field.KI();
    out.KIIref = field.KII();
    out.Jref = (out.KIref * out.KIref + out.KIIref * out.KIIref) / Eeff;
    if (!contourCrackCrossing(crack.points, tip, radius, crossing)) return out;
    const JIntegralResult j = jIntegral(samples, crack.tipPosition(tip), crack.tipDirection(tip), crossing, segments,
                                        ContourSettings{radius, 16, c.dx, m.shearModulus(), m.kolosov(c.analysis)});
    if (!j.valid) return out;
    const StressIntensity k = stressIntensityFromInteraction(j.J, j.KIinteraction, j.KIIinteraction, Eeff);
    out.J = j.J;
    out.KI = k.KI;
    out.KII = k.KII;
    out.valid = true;
    return out;
}

} // namespace shatter::mpm::validation
