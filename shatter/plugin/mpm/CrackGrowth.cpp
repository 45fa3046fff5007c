#include <shatter/plugin/mpm/CrackGrowth.h>

#include <shatter/plugin/mpm/BSpline.h>
#include <shatter/plugin/mpm/CrackParticleSplit.h>
#include <shatter/plugin/mpm/GridToParticle.h>
#include <shatter/plugin/mpm/HoopStress.h>
#include <shatter/plugin/mpm/JIntegral.h>
#include <shatter/plugin/mpm/Shape.h>
#include <shatter/plugin/mpm/StressIntensity.h>

#include <algorithm>
#include <cmath>

namespace shatter::mpm {

namespace {

struct TipSurroundings {
    std::vector<NearTipSample> samples;
    int material = 0;      // of the particle nearest to the tip
};

TipSurroundings surroundings(const SimulationState& s, const Vec2& centre, double reach) {
    const Particles& P = s.particles;
    TipSurroundings out;
    double nearest = INFINITY;
    const double reach2 = reach * reach;
    for (size_t p = 0; p < P.size(); ++p) {
        const double d2 = (P.x[p] - centre).squaredNorm();
        if (d2 > reach2) continue;
        if (d2 < nearest) nearest = d2, out.material = P.material[p];
        const ModelConstants& model = s.models[P.material[p]];
        const double Jp = P.Fp[p].determinant();
        const Mat2 F = P.Fe[p] * P.Fp[p];
        NearTipSample q;
        q.x = P.x[p];
        q.mass = P.mass[p];
        q.volume = P.volume0[p];
        q.sigma = s.stress[p] / F.determinant();
        q.gradU = F - Mat2::Identity();
        q.W = energyDensity(model, P.Fe[p], Jp);
        q.kinetic = 0.5 * P.mass[p] / P.volume0[p] * P.v[p].squaredNorm();
        out.samples.push_back(q);
    }
    return out;
}

double contourRadius(const SimulationState& s) { return s.scene.fracture.contourRadiusCells * s.scene.grid.dx; }

// Analyses one tip. `nearOutline` is set when the contour could be built geometrically but
// left the material (the tip is within a contour radius of the body's outline).
TipResult analyseTip(const SimulationState& s, int c, int t, TipSurroundings& around, bool& nearOutline) {
    nearOutline = false;
    const Crack& crack = s.cracks[size_t(c)];
    TipResult r;
    r.crack = c;
    r.tip = t;
    r.position = crack.tipPosition(t);
    r.grew = crack.tips[size_t(t)].result.grew;
    const double radius = contourRadius(s), dx = s.scene.grid.dx;
    around = surroundings(s, r.position, radius + (kernelRadius(KernelType::Cubic) + 0.5) * dx);
    Vec2 crossing;
    if (!contourCrackCrossing(crack.points, t, radius, crossing)) return r;
    const Vec2 direction = crack.tipDirection(t);
    const Material& m = s.scene.materials[size_t(around.material)];
    const ContourSettings contour{radius, s.scene.fracture.contourSegments, dx, m.shearModulus(),
                                  m.kolosov(s.scene.analysis)};
    const JIntegralResult j = jIntegral(around.samples, r.position, direction, crossing, s.segments, contour);
    r.contour = j.contour;
    if (!j.valid) {
        nearOutline = true;
        return r;
    }
    const StressIntensity k = stressIntensityFromInteraction(j.J, j.KIinteraction, j.KIIinteraction,
                                                             m.effectiveModulus(s.scene.analysis));
    r.J = j.J;
    r.KI = k.KI;
    r.KII = k.KII;
    r.theta = std::abs(k.KII) <= s.scene.fracture.mixityTolerance * std::abs(k.KI) ? 0.0 : kinkAngle(k.KI, k.KII);
    r.valid = true;
    return r;
}

struct WaveSpeeds {
    double shear, rayleigh;
};

WaveSpeeds waveSpeeds(const Material& m) {
    const double cs = std::sqrt(m.shearModulus() / m.rho);
    // Viktorov's approximation of the Rayleigh speed, within 0.5% for 0 <= ν <= 0.5.
    return {cs, cs * (0.862 + 1.14 * m.nu) / (1 + m.nu)};
}

void filter(CrackTip& tip, const TipResult& r, double dt, double timeConstant) {
    if (!tip.filterPrimed || timeConstant <= 0) {
        tip.filteredKI = r.KI;
        tip.filteredKII = r.KII;
        tip.filterPrimed = true;
        return;
    }
    const double a = 1 - std::exp(-dt / timeConstant);
    tip.filteredKI += a * (r.KI - tip.filteredKI);
    tip.filteredKII += a * (r.KII - tip.filteredKII);
}

// Σ N V / dx² at p: ≈ 1 inside the material, ½ on its outline, 0 outside.
double materialDensity(const std::vector<NearTipSample>& samples, const Vec2& p, double dx) {
    double d = 0;
    for (const NearTipSample& q : samples) d += pointWeight<CubicSpline>(q.x - p, 1 / dx) * q.volume;
    return d / (dx * dx);
}

// Cracks do not run into themselves or each other (merging is not modelled): a step whose
// new segment crosses, or ends within half a step of, an existing segment other than the
// tip's own last one is refused and the tip waits for the field to change.
bool stepIsClear(const SimulationState& s, int c, int t, const Vec2& from, const Vec2& to, double growth) {
    const Crack& own = s.cracks[size_t(c)];
    const size_t n = own.points.size();
    for (size_t k = 0; k < s.cracks.size(); ++k) {
        const auto& pts = s.cracks[k].points;
        for (size_t i = 0; i + 1 < pts.size(); ++i) {
            const bool ownLast = int(k) == c && (t == 0 ? i == 0 : i + 2 == n);
            if (ownLast) continue;
            const Vec2 a = pts[i], b = pts[i + 1], d = b - a;
            const double u = std::clamp((to - a).dot(d) / d.squaredNorm(), 0.0, 1.0);
            if ((to - (a + u * d)).norm() < 0.5 * growth) return false;
            const bool ownNeighbour = int(k) == c && (t == 0 ? i == 1 : i + 3 == n);
            if (!ownNeighbour && segmentsIntersect(from, to, a, b)) return false;
        }
    }
    return true;
}

// A tip's analysis, done before its growth decision.
struct TipAnalysis {
    int crack = 0, tip = 0;
    TipResult result;
    TipSurroundings around;
    bool nearOutline = false;
};

// Decides the growth of one tip from its analysis `a` (of the current crack geometry).
void tryToGrow(SimulationState& s, const TipAnalysis& a, double dt) {
    const int c = a.crack, t = a.tip;
    Crack& crack = s.cracks[size_t(c)];
    CrackTip& tip = crack.tips[size_t(t)];
    const TipSurroundings& around = a.around;
    const bool nearOutline = a.nearOutline;
    const TipResult& r = a.result;
    const Material& m = s.scene.materials[size_t(around.material)];
    const WaveSpeeds speeds = waveSpeeds(m);
    const CrackGrowthSettings& f = s.scene.fracture;
    const double dx = s.scene.grid.dx, growth = f.growthCells * dx;
    if (r.valid) {
        tip.result = r;
        filter(tip, r, dt, f.filterTransits * 2 * contourRadius(s) / speeds.shear);
    } else {
        // No J: show where the tip is, keep the last values.
        tip.result.crack = r.crack;
        tip.result.tip = r.tip;
        tip.result.position = r.position;
        tip.result.contour = r.contour;
        tip.result.valid = false;
    }
    if (!tip.filterPrimed) return;
    // Without a valid contour a tip only runs on straight, and only near the outline (the
    // contour leaves the body there; the last valid K carries it through). Anywhere else, e.g.
    // a crack that curled back into its own contour, it waits.
    const bool straightOnly = !r.valid;
    if (straightOnly && !nearOutline) return;
    if (s.time - tip.lastGrowthTime < growth / (f.speedLimit * speeds.rayleigh)) return;
    const Vec2 position = crack.tipPosition(t), direction = crack.tipDirection(t);
    double theta = 0;
    if (straightOnly) {
        theta = 0;
    } else if (!tip.guide.empty()) {
        const Vec2 to = tip.guide.front() - position;
        theta = std::atan2(direction.x() * to.y() - direction.y() * to.x(), direction.dot(to));
    } else if (std::abs(tip.filteredKII) > f.mixityTolerance * std::abs(tip.filteredKI)) {
        theta = kinkAngle(tip.filteredKI, tip.filteredKII);
    }
    if (effectiveStressIntensity(tip.filteredKI, tip.filteredKII, theta) < m.Kc) return;
    Vec2 next = position + growth * Vec2(std::cos(theta) * direction.x() - std::sin(theta) * direction.y(),
                                         std::sin(theta) * direction.x() + std::cos(theta) * direction.y());
    const bool guided = !straightOnly && !tip.guide.empty();
    if (guided) next = tip.guide.front();
    if (!stepIsClear(s, c, t, position, next, growth)) return;
    if (guided) tip.guide.pop_front();
    crack.extend(t, next);
    // The faces of the new step end at the crack line, not at the lattice rows (CrackParticleSplit.h).
    if (splitParticlesAtGrowth(crack, t, s.spacing, s.particles) > 0) updateAfterParticleEdit(s);
    tip.lastGrowthTime = s.time;
    tip.result.theta = theta;
    ++tip.result.grew;
    // Past the outline the crack is through: this tip stops.
    if (materialDensity(around.samples, next, dx) < 0.3) tip.exited = true;
}

} // namespace

void analyseAllTips(SimulationState& s) {
    s.segments.rebuild(s.cracks, crackEndGap(s));
    for (size_t c = 0; c < s.cracks.size(); ++c)
        for (int t = 0; t < 2; ++t) {
            CrackTip& tip = s.cracks[c].tips[size_t(t)];
            if (!tip.active || tip.exited) continue;
            TipSurroundings around;
            bool nearOutline = false;
            const TipResult r = analyseTip(s, int(c), t, around, nearOutline);
            if (r.valid) {
                tip.result = r;
            } else {
                // Keep the last J and K (e.g. near the outline) but show where the tip is.
                tip.result.crack = r.crack;
                tip.result.tip = r.tip;
                tip.result.position = r.position;
                tip.result.contour = r.contour;
                tip.result.valid = false;
            }
        }
}

namespace {

// Whether the propagating tips are analysed after this substep of length `dt`: every N
// substeps, N the substeps the fastest wave takes to cross CrackGrowthSettings::analysisCells.
bool tipAnalysisDue(const SimulationState& s, double dt) {
    if (s.lastTipAnalysisSubstep < 0) return true;
    const double substeps = s.scene.fracture.analysisCells * s.scene.grid.dx / (s.fastestSignal * dt);
    const long interval = std::max(1L, long(std::min(substeps, 1e9)));
    return s.substeps - s.lastTipAnalysisSubstep >= interval;
}

} // namespace

void growCracks(SimulationState& s, double dt) {
    if (!tipAnalysisDue(s, dt)) return;
    // The low-pass filter integrates over the time since the last analysis.
    const double elapsed = s.lastTipAnalysisSubstep < 0 ? dt : s.time - s.lastTipAnalysisTime;
    s.lastTipAnalysisSubstep = s.substeps;
    s.lastTipAnalysisTime = s.time;
    s.segments.rebuild(s.cracks, crackEndGap(s)); // the crack particles moved since
    std::vector<TipAnalysis> analyses;
    for (size_t c = 0; c < s.cracks.size(); ++c)
        for (int t = 0; t < 2; ++t) {
            const CrackTip& tip = s.cracks[c].tips[size_t(t)];
            if (tip.propagates && !tip.exited) analyses.push_back(TipAnalysis{int(c), t, {}, {}, false});
        }
    // The analyses (a scan of the particles and the J-integral: most of the cost) only read
    // the state, so the tips are analysed in parallel; the growth decisions then run in tip
    // order. A tip that grew changes the geometry the later tips' analyses saw, so after a
    // growth the later tips are analysed again: the result is that of analysing and growing
    // one tip after the other, whatever the thread count.
    const long count = long(analyses.size());
#pragma omp parallel for schedule(dynamic, 1) num_threads(s.threads)
    for (long k = 0; k < count; ++k) {
        TipAnalysis& a = analyses[size_t(k)];
        a.result = analyseTip(s, a.crack, a.tip, a.around, a.nearOutline);
    }
    bool grown = false;
    for (TipAnalysis& a : analyses) {
        if (grown) a.result = analyseTip(s, a.crack, a.tip, a.around, a.nearOutline);
        const int before = s.cracks[size_t(a.crack)].tips[size_t(a.tip)].result.grew;
        tryToGrow(s, a, elapsed);
        grown = grown || s.cracks[size_t(a.crack)].tips[size_t(a.tip)].result.grew != before;
    }
}

} // namespace shatter::mpm
