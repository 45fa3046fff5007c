#include <shatter/plugin/mpm/SceneCheck.h>

#include <shatter/plugin/common/InputError.h>
#include <shatter/plugin/common/QuotedInput.h>
#include <shatter/plugin/mpm/ConstitutiveModel.h>

#include <charconv>
#include <cmath>
#include <cstdio>

namespace shatter::mpm {

namespace {

class Checker {
public:
    explicit Checker(const Scene& scene) : scene_(scene) {}

    [[noreturn]] void fail(const std::string& key, const std::string& what) const {
        throw InputError((scene_.source.empty() ? std::string() : scene_.source + ": ") + printableInput(key, 200) + ": " + what);
    }
    void finite(const std::string& key, double v) const {
        if (!std::isfinite(v)) fail(key, "must be a finite number");
    }
    void positive(const std::string& key, double v) const {
        finite(key, v);
        if (v <= 0) fail(key, "must be > 0, got " + text(v));
    }
    void nonNegative(const std::string& key, double v) const {
        finite(key, v);
        if (v < 0) fail(key, "must be >= 0, got " + text(v));
    }
    void finite(const std::string& key, const Vec2& v) const {
        if (!v.allFinite()) fail(key, "must hold finite numbers");
    }
    void box(const std::string& key, const Box& b) const {
        finite(key + ".min", b.min);
        finite(key + ".max", b.max);
        if (b.min.x() > b.max.x() || b.min.y() > b.max.y()) fail(key, "min must not exceed max");
    }
    // The shortest text that reads back as v (0.4999999, not 0.5).
    static std::string text(double v) {
        char buffer[32];
        const auto end = std::to_chars(buffer, buffer + sizeof buffer, v).ptr;
        return std::string(buffer, end);
    }

private:
    const Scene& scene_;
};

void checkMaterial(const Checker& c, const Material& m, Analysis analysis) {
    const std::string key = "materials." + m.name;
    c.positive(key + ".E", m.E);
    c.finite(key + ".nu", m.nu);
    if (m.nu >= 0.5) c.fail(key + ".nu", "must be below 0.5 (0.5 is incompressible), got " + Checker::text(m.nu));
    // In plane strain λ = Eν/((1+ν)(1−2ν)) grows without bound as ν → 0.5, and the CFL step
    // shrinks with it: at 0.4999999 the step is 2000 times shorter than at 0.3.
    if (analysis == Analysis::PlaneStrain && m.nu >= kMaxPlaneStrainNu)
        c.fail(key + ".nu", "must be below 0.5 - 1e-6 in plane strain (nearly incompressible: the wave speed and the "
                            "substep count grow without bound), got " + Checker::text(m.nu));
    if (m.nu <= -1) c.fail(key + ".nu", "must be above -1, got " + Checker::text(m.nu));
    c.positive(key + ".rho", m.rho);
    if (!(m.Kc > 0)) c.fail(key + ".Kc", "must be > 0, got " + Checker::text(m.Kc));
    if (m.model == ConstitutiveModelType::Snow) {
        c.positive(key + ".theta_c", m.thetaC);
        if (m.thetaC >= 1) c.fail(key + ".theta_c", "must be below 1, got " + Checker::text(m.thetaC));
        c.nonNegative(key + ".theta_s", m.thetaS);
        c.nonNegative(key + ".xi", m.xi);
    }
}

void checkShape(const Checker& c, const std::string& key, const Shape& shape) {
    if (auto r = std::get_if<RectShape>(&shape.variant())) {
        c.finite(key + ".min", r->min);
        c.finite(key + ".max", r->max);
        if (!(r->min.array() < r->max.array()).all()) c.fail(key, "min must be below max on both axes");
    } else if (auto ci = std::get_if<CircleShape>(&shape.variant())) {
        c.finite(key + ".center", ci->center);
        c.positive(key + ".radius", ci->radius);
    } else {
        const auto& pts = std::get<PolygonShape>(shape.variant()).points;
        if (pts.size() < 3) c.fail(key + ".points", "needs at least 3 points");
        for (const Vec2& p : pts) c.finite(key + ".points", p);
        if (signedDoubleArea(pts) == 0) c.fail(key + ".points", "encloses no area");
        if (selfIntersects(pts)) c.fail(key + ".points", "outline crosses itself");
    }
}

bool crackTouchesBody(const Scene& scene, const CrackSpec& crack) {
    for (size_t k = 0; k + 1 < crack.points.size(); ++k) {
        const Vec2 a = crack.points[k], b = crack.points[k + 1];
        const int samples = 64;
        for (int i = 0; i <= samples; ++i)
            if (insideAnyBody(scene, a + (b - a) * (double(i) / samples))) return true;
    }
    return false;
}

void checkCrack(const Checker& c, const Scene& scene, size_t index) {
    const CrackSpec& crack = scene.cracks[index];
    const std::string key = "cracks[" + std::to_string(index) + "]";
    if (crack.points.size() < 2) c.fail(key + ".points", "needs at least 2 points");
    for (size_t k = 0; k < crack.points.size(); ++k) {
        c.finite(key + ".points", crack.points[k]);
        if (k > 0 && crack.points[k] == crack.points[k - 1])
            c.fail(key + ".points", "points " + std::to_string(k - 1) + " and " + std::to_string(k) + " coincide");
        // The solver resolves a crack to fracture.growth (half a cell); much shorter segments
        // add nothing but cost: 3000 points within one cell made a substep take a second.
        const double length = k > 0 ? (crack.points[k] - crack.points[k - 1]).norm() : INFINITY;
        if (length < kMinCrackSegmentCells * scene.grid.dx)
            c.fail(key + ".points", "points " + std::to_string(k - 1) + " and " + std::to_string(k) + " are " +
                                        Checker::text(length) + " m apart, less than " + Checker::text(kMinCrackSegmentCells) +
                                        " x grid.dx (the crack is resolved to half a cell)");
    }
    if (!crackTouchesBody(scene, crack)) c.fail(key, "lies outside every body");
    const bool start = crack.tips == TipSelection::Both || crack.tips == TipSelection::Start;
    const bool end = crack.tips == TipSelection::Both || crack.tips == TipSelection::End;
    auto tipInside = [&](bool selected, const Vec2& p, const char* which, const char* other) {
        if (selected && !insideAnyBody(scene, p))
            c.fail(key + ".tips", std::string("the ") + which + " tip (" + Checker::text(p.x()) + ", " +
                                      Checker::text(p.y()) + ") lies outside every body; use \"" + other +
                                      "\" or \"none\"");
    };
    tipInside(start, crack.points.front(), "start", "end");
    tipInside(end, crack.points.back(), "end", "start");
    for (const Vec2& p : crack.guide) c.finite(key + ".guide", p);
    if (!crack.guide.empty() && crack.tips == TipSelection::None)
        c.fail(key + ".guide", "has no tip to guide (tips is \"none\")");
}

std::string brief(double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%.3g", v);
    return text;
}

// A body faster than kMaxBodySpeed is beyond what the solver models (elastic fracture, not
// hypervelocity impact), and a wave speed or body speed that makes the CFL step shorter than
// kMinTimeStep would need more than 10^12 substeps per simulated second.
void checkSignalSpeed(const Checker& c, const Scene& scene, size_t b) {
    const Body& body = scene.bodies[b];
    const std::string key = "bodies[" + std::to_string(b) + "]";
    const double speed = body.velocity.norm();
    if (speed > kMaxBodySpeed)
        c.fail(key + ".velocity", "speed " + Checker::text(speed) + " m/s is above the limit of " +
                                      Checker::text(kMaxBodySpeed) + " m/s");
    const Material& m = scene.materials[size_t(body.material)];
    const double wave = ModelConstants::of(m, scene.analysis).waveSpeed0;
    const double step = scene.time.cfl * scene.grid.dx / (wave + speed);
    if (!(step >= kMinTimeStep))
        c.fail("materials." + m.name, "E = " + brief(m.E) + " Pa and rho = " + brief(m.rho) + " kg/m^3 give a wave speed of " +
                                          brief(wave) + " m/s: with grid.dx = " + brief(scene.grid.dx) +
                                          " m the CFL step is " + brief(step) + " s, below the limit of " +
                                          brief(kMinTimeStep) + " s");
}

} // namespace

bool insideAnyBody(const Scene& scene, const Vec2& p) {
    for (const Body& b : scene.bodies)
        if (b.shape.contains(p)) return true;
    return false;
}

void checkScene(const Scene& scene) {
    const Checker c(scene);
    c.positive("grid.dx", scene.grid.dx);
    if (scene.grid.ppc < 1) c.fail("grid.ppc", "must be >= 1, got " + std::to_string(scene.grid.ppc));
    c.nonNegative("grid.jitter", scene.grid.jitter);
    if (scene.grid.jitter >= 1) c.fail("grid.jitter", "must be below 1 (a fraction of the particle spacing)");
    c.positive("time.end", scene.time.end);
    c.positive("time.frame", scene.time.frame);
    c.positive("time.cfl", scene.time.cfl);
    if (scene.time.cfl > 1) c.fail("time.cfl", "must be at most 1, got " + Checker::text(scene.time.cfl));
    if (!(scene.time.maxStep > 0)) c.fail("time.max_step", "must be > 0");
    c.finite("gravity", scene.gravity);
    c.nonNegative("damping", scene.damping);
    if (scene.materials.empty()) c.fail("materials", "needs at least one material");
    for (const Material& m : scene.materials) checkMaterial(c, m, scene.analysis);
    if (scene.bodies.empty()) c.fail("bodies", "needs at least one body");
    for (size_t b = 0; b < scene.bodies.size(); ++b) {
        const std::string key = "bodies[" + std::to_string(b) + "]";
        checkShape(c, key + ".shape", scene.bodies[b].shape);
        if (scene.bodies[b].material < 0 || size_t(scene.bodies[b].material) >= scene.materials.size())
            c.fail(key + ".material", "is not one of the scene's materials");
        c.finite(key + ".velocity", scene.bodies[b].velocity);
        checkSignalSpeed(c, scene, b);
    }
    for (size_t k = 0; k < scene.cracks.size(); ++k) checkCrack(c, scene, k);
    for (size_t k = 0; k < scene.loads.size(); ++k) {
        const std::string key = "loads[" + std::to_string(k) + "]";
        c.box(key + ".region", scene.loads[k].region);
        const Load& load = scene.loads[k];
        if (load.kind == Load::Kind::Pressure)
            c.finite(key + ".pressure", load.pressure);
        else
            c.finite(key + (load.kind == Load::Kind::Traction ? ".traction" : ".force"), load.value);
        c.finite(key + ".facing", load.facing);
        if (load.kind == Load::Kind::Force && load.facing != Vec2::Zero())
            c.fail(key + ".facing", "applies to traction and pressure loads (a force acts on particles, not the outline)");
        c.nonNegative(key + ".ramp", scene.loads[k].ramp);
    }
    for (size_t k = 0; k < scene.fixed.size(); ++k) c.box("fixed[" + std::to_string(k) + "]", scene.fixed[k]);
    const CrackGrowthSettings& f = scene.fracture;
    c.positive("fracture.contour_radius", f.contourRadiusCells);
    if (f.contourSegments < 2 || f.contourSegments % 2)
        c.fail("fracture.contour_segments", "must be an even number >= 2 (Simpson's rule)");
    c.positive("fracture.growth", f.growthCells);
    c.nonNegative("fracture.mixity_tolerance", f.mixityTolerance);
    c.positive("fracture.speed_limit", f.speedLimit);
    c.nonNegative("fracture.filter", f.filterTransits);
    c.nonNegative("fracture.analysis_interval", f.analysisCells);
}

} // namespace shatter::mpm
