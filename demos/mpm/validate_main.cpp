// shatter-mpm-validate [--quick | --full | --grid-offsets | --inclined-shifts] [--threads T]: the 2D crack solver
// against exact and handbook fracture mechanics; prints a table of computed vs. reference
// values and exits with 1 when any row misses its bound. --quick is what CTest runs
// (mpm.validate_quick); the default adds tip positions and the crack anywhere on the grid
// (crack-line and tip offsets at a/dx = 16, and a crack running with its line off the grid
// lines); --full adds the fine resolutions (several
// minutes); --grid-offsets runs only the crack-anywhere rows; --inclined-shifts prints the
// inclined crack moved along itself (notes, no bounds).
#include <shatter/plugin/mpm/Diagnostics.h>
#include <shatter/plugin/mpm/HoopStress.h>
#include <shatter/plugin/mpm/Solver2D.h>
#include <shatter/plugin/mpm/validation/CentreCrackFiniteElement.h>
#include <shatter/plugin/mpm/validation/CentreCrackedPlate.h>
#include <shatter/plugin/mpm/validation/ExactFieldCheck.h>
#include <shatter/plugin/mpm/validation/InclinedCrack.h>

#include <CLI/CLI.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

namespace {

using namespace shatter::mpm;
using namespace shatter::mpm::validation;

constexpr double kDegree = std::numbers::pi / 180;

class Table {
public:
    Table() {
        std::printf("%-52s %13s %13s %9s %8s  %s\n", "case", "computed", "reference", "error", "bound", "result");
        std::printf("%s\n", std::string(108, '-').c_str());
    }
    // Relative error |computed/reference − 1| against `bound`.
    void relative(const std::string& name, double computed, double reference, double bound) {
        const double error = std::abs(computed / reference - 1);
        row(name, computed, reference, formatted("%.2f%%", 100 * error), formatted("%.1f%%", 100 * bound), error <= bound);
    }
    // Absolute difference against `bound`, with a unit for the error column.
    void absolute(const std::string& name, double computed, double reference, double bound, const char* unit) {
        const double error = std::abs(computed - reference);
        row(name, computed, reference, formatted("%.3g", error) + unit, formatted("%.3g", bound) + unit, error <= bound);
    }
    void check(const std::string& name, double computed, const std::string& requirement, bool ok) {
        std::printf("%-52s %13.6g %13s %9s %8s  %s\n", name.c_str(), computed, requirement.c_str(), "", "",
                    ok ? "pass" : "FAIL");
        failed_ += ok ? 0 : 1;
    }
    void note(const std::string& text) { std::printf("  %s\n", text.c_str()); }
    int failed() const { return failed_; }

private:
    static std::string formatted(const char* f, double v) {
        char s[64];
        std::snprintf(s, sizeof s, f, v);
        return s;
    }
    void row(const std::string& name, double c, double r, const std::string& e, const std::string& b, bool ok) {
        std::printf("%-52s %13.6g %13.6g %9s %8s  %s\n", name.c_str(), c, r, e.c_str(), b.c_str(), ok ? "pass" : "FAIL");
        std::fflush(stdout);
        failed_ += ok ? 0 : 1;
    }
    int failed_ = 0;
};

// The finite-element reference of the plate `c` (CentreCrackFiniteElement.h): rows for K_I
// (the worse tip) against it, and a note with its meshes and how far its finite height puts
// it from Tada's strip.
void againstFiniteElement(Table& t, const std::string& name, const CentreCrackedPlateCase& c, double KI, double bound) {
    const CentreCrackFiniteElementCase fc = finiteElementCase(c);
    const CentreCrackFiniteElementResult fe = centreCrackFiniteElement(fc);
    t.relative(name + " vs FE", KI, fe.KI, bound);
    char info[256];
    std::snprintf(info, sizeof info,
                  "(FE, plate %gx%g, a %g: F %.5f %.5f %.5f -> %.5f (order %.2f, est. error %.1e, %s); Tada %.5f, "
                  "FE/Tada %+.3f%%)",
                  fc.width, fc.height, fc.a, fe.meshes[0].KI / fe.KI * fe.F(fc), fe.meshes[1].KI / fe.KI * fe.F(fc),
                  fe.meshes[2].KI / fe.KI * fe.F(fc), fe.F(fc), fe.order, fe.errorEstimate,
                  fe.converged ? "converged" : "NOT converged", tadaCentreCrack(2 * fc.a / fc.width),
                  100 * (fe.F(fc) / tadaCentreCrack(2 * fc.a / fc.width) - 1));
    t.note(info);
    t.check(name + ": FE reference converged", fe.errorEstimate, "finest 2 < 0.1%", fe.converged);
}

// The finite-element reference itself against closed forms, before it is used: a tall strip
// (Tada within its 0.1%) and a small crack (Griffith).
void finiteElementReference(Table& t) {
    CentreCrackFiniteElementCase strip;
    strip.height = 8;
    const auto s = centreCrackFiniteElement(strip);
    t.relative("FE reference, strip H=8W 2a/W=0.5: F vs Tada", s.F(strip), tadaCentreCrack(0.5), 2e-3);
    CentreCrackFiniteElementCase small;
    small.height = 4;
    small.a = 0.025;
    small.divisions = 4;
    const auto g = centreCrackFiniteElement(small);
    t.relative("FE reference, 2a/W=0.05 H=4W: F vs Griffith (1)", g.F(small), 1.0, 3e-3);
}

void exactField(Table& t) {
    struct Case {
        const char* name;
        double sigma, tau, angle;
    };
    for (const Case& c : {Case{"mode I", 1e6, 0, 0}, Case{"mode II", 0, 1e6, 0}, Case{"mixed, crack at 30°", 1e6, 6e5, 30}}) {
        ExactFieldCase e;
        e.sigma = c.sigma;
        e.tau = c.tau;
        e.angle = c.angle * kDegree;
        const ExactFieldResult r = runExactFieldCase(e);
        const std::string prefix = std::string("J routine on Westergaard field, ") + c.name;
        if (c.sigma != 0) t.relative(prefix + ": K_I", r.KI, r.KIref, 5e-3);
        if (c.tau != 0) t.relative(prefix + ": K_II", r.KII, r.KIIref, 5e-3);
    }
}

// K_I of the tip farther from the handbook value.
double worseTip(const CentreCrackedPlateResult& r) {
    return std::abs(r.KIstart / r.KIreference - 1) > std::abs(r.KIend / r.KIreference - 1) ? r.KIstart : r.KIend;
}

void centreCrack(Table& t, const std::vector<double>& lambdas, double aOverDx, double bound, int threads) {
    for (double lambda : lambdas) {
        CentreCrackedPlateCase c;
        c.lambda = lambda;
        c.aOverDx = aOverDx;
        c.threads = threads;
        const auto start = std::chrono::steady_clock::now();
        const CentreCrackedPlateResult r = runCentreCrackedPlate(c);
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        char name[96];
        std::snprintf(name, sizeof name, "centre crack 2a/W=%.2f a/dx=%g: K_I, start tip", r.lambda, r.aOverDx);
        t.relative(name, r.KIstart, r.KIreference, bound);
        std::snprintf(name, sizeof name, "centre crack 2a/W=%.2f a/dx=%g: K_I, end tip", r.lambda, r.aOverDx);
        t.relative(name, r.KIend, r.KIreference, bound);
        std::snprintf(name, sizeof name, "centre crack 2a/W=%.2f a/dx=%g: K_I", r.lambda, r.aOverDx);
        againstFiniteElement(t, name, c, worseTip(r), bound);
        std::snprintf(name, sizeof name, "centre crack 2a/W=%.2f a/dx=%g: |K_II|/K_I", r.lambda, r.aOverDx);
        t.absolute(name, std::max(std::abs(r.KIIstart), std::abs(r.KIIend)) / r.KIreference, 0, 0.02, "");
        char info[160];
        std::snprintf(info, sizeof info, "(%ld particles, %ld substeps, %s, %.1f s)", r.particles, r.substeps,
                      r.converged ? "settled" : "NOT settled", seconds);
        t.note(info);
    }
}

// Tips between grid lines. A discrete crack ends at a grid node, the one nearest to its true
// end (LineCrossing.h), so K_I is that of a crack up to half a cell longer or shorter. The
// bound of each row is what that rounding alone does to Tada's K at this a/dx and λ, plus 1%
// (the aligned case's error): e.g. 1/8 cell: |Δa| = dx/8, K moves by 1.4% at λ ≈ 0.6.
void offGrid(Table& t, const std::vector<double>& fractions, int threads) {
    for (double f : fractions) {
        CentreCrackedPlateCase c;
        c.aOverDx = 10 + f;
        c.widthCells = 34; // centre on a grid line, tips f cells past one
        c.lambda = 2 * c.aOverDx / 34;
        c.threads = threads;
        const CentreCrackedPlateResult r = runCentreCrackedPlate(c);
        const double snapped = std::round(c.aOverDx); // the node the discrete crack ends at
        const double rounding = std::abs(tadaCentreCrack(2 * snapped / 34) * std::sqrt(snapped) /
                                             (tadaCentreCrack(r.lambda) * std::sqrt(c.aOverDx)) -
                                         1);
        char name[96];
        std::snprintf(name, sizeof name, "centre crack, tips %g cell past a grid line (a/dx=%g): K_I", f, c.aOverDx);
        const double worse = worseTip(r); // of the two tips (equal by symmetry)
        t.relative(name, worse, r.KIreference, rounding + 0.01);
        againstFiniteElement(t, name, c, worse, rounding + 0.01);
    }
}

// The crack anywhere on the grid (issue 20): a symmetric centre crack in pure tension, plane
// strain, 2a/W = 0.5 at a/dx = 16 (width 64 cells, height 128, the plate), the scene
// file's default discretisation (cubic kernel, 2 particles per cell per axis), the crack
// line `line` cells above a grid line and the tips `tip` cells past one. K_I within 2% of
// Tada's K for the true crack, |K_II|/K_I below 1% at every transit after the load ramp
// (steady: no creep).
void anywhereOnGrid(Table& t, const std::vector<std::pair<double, double>>& offsets, int threads) {
    for (const auto& [line, tip] : offsets) {
        CentreCrackedPlateCase c;
        c.aOverDx = 16 + tip;
        c.widthCells = 64;
        c.lambda = 2 * c.aOverDx / 64;
        c.lineOffset = line;
        c.analysis = Analysis::PlaneStrain;
        c.kernel = KernelType::Cubic;
        c.ppc = 2;
        c.threads = threads;
        const auto start = std::chrono::steady_clock::now();
        const CentreCrackedPlateResult r = runCentreCrackedPlate(c);
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        char name[96];
        std::snprintf(name, sizeof name, "crack line +%.3g, tips +%.3g cell (a/dx=%g): K_I", line, tip, c.aOverDx);
        const double worse = worseTip(r);
        t.relative(name, worse, r.KIreference, 0.02);
        std::snprintf(name, sizeof name, "crack line +%.3g, tips +%.3g cell: K_I", line, tip);
        againstFiniteElement(t, name, c, worse, 0.02);
        double mixity = 0; // worst after the ramp (the first transit)
        for (size_t k = 1; k < r.mixityHistory.size(); ++k) mixity = std::max(mixity, r.mixityHistory[k]);
        std::snprintf(name, sizeof name, "crack line +%.3g, tips +%.3g cell: |K_II|/K_I, worst transit", line, tip);
        t.absolute(name, mixity, 0, 0.01, "");
        char info[256];
        int used = std::snprintf(info, sizeof info, "(K_I %.6g / %.6g, %s, %.1f s; |K_II|/K_I per transit:", r.KIstart,
                                 r.KIend, r.converged ? "settled" : "NOT settled", seconds);
        for (double m : r.mixityHistory)
            if (used < int(sizeof info) - 12) used += std::snprintf(info + used, sizeof info - size_t(used), " %.4f", m);
        t.note(std::string(info) + ")");
    }
}

// A running crack anywhere on the grid (issue 20): the plate of anywhereOnGrid with its crack
// line `line` cells above a grid line, growing under a toughness of 0.95 × Tada's K_I until
// each tip has taken 12 steps (6 cells). The growth decision reads the low-pass filtered K
// (CrackGrowth.h): its |K_II|/K_I stays below the 2% dead band, so the crack grows straight,
// and the path stays within 0.01 cell of the line. The worst unfiltered |K_II|/K_I of any
// analysis is printed beside.
void runningCrack(Table& t, const std::vector<double>& lines, int threads) {
    for (double line : lines) {
        CentreCrackedPlateCase c;
        c.aOverDx = 16;
        c.widthCells = 64;
        c.lambda = 0.5;
        c.lineOffset = line;
        c.analysis = Analysis::PlaneStrain;
        c.kernel = KernelType::Cubic;
        c.ppc = 2;
        Scene scene = centreCrackedPlateScene(c);
        scene.cracks[0].propagate = true;
        scene.materials[0].Kc = 0.95 * tadaCentreCrack(0.5) * c.sigma * std::sqrt(std::numbers::pi * 16);
        Solver2D solver(scene);
        if (threads > 0) solver.setThreads(threads);
        const double y = scene.cracks[0].points[0].y();
        const size_t initial = solver.cracks()[0].points.size();
        double filtered = 0, raw = 0;
        while (solver.cracks()[0].points.size() < initial + 24 && solver.time() < scene.time.end) {
            solver.step(1.0);
            if (solver.cracks()[0].points.size() == initial) continue; // not running yet
            for (const CrackTip& tip : solver.cracks()[0].tips) {
                if (tip.filteredKI > 0) filtered = std::max(filtered, std::abs(tip.filteredKII / tip.filteredKI));
                if (tip.result.KI > 0) raw = std::max(raw, std::abs(tip.result.KII / tip.result.KI));
            }
        }
        double off = 0;
        for (const Vec2& p : solver.cracks()[0].points) off = std::max(off, std::abs(p.y() - y));
        char name[96];
        std::snprintf(name, sizeof name, "running crack, line +%.3g cell: growth steps", line);
        const long steps = long(solver.cracks()[0].points.size() - initial);
        t.check(name, double(steps), ">= 24", steps >= 24);
        std::snprintf(name, sizeof name, "running crack, line +%.3g cell: |K_II|/K_I filtered", line);
        t.absolute(name, filtered, 0, 0.02, "");
        std::snprintf(name, sizeof name, "running crack, line +%.3g cell: off the line (cells)", line);
        t.absolute(name, off, 0, 0.01, "");
        char info[96];
        std::snprintf(info, sizeof info, "(unfiltered |K_II|/K_I, worst analysis: %.4f)", raw);
        t.note(info);
    }
}

// The inclined crack moved along itself by a share of a cell, so that its tips fall
// elsewhere in their cells. Notes, not rows: at a/dx = 8 its K_II misses 5% at some shifts
// with every crack-end rule tried so far (LineCrossing.h), so the one position of the
// inclinedCrack rows is a weak check of the crack ends.
void inclinedCrackShifted(Table& t, double aOverDx, int threads) {
    for (double shift : {0.0, 0.25, 0.5, 0.75}) {
        InclinedCrackCase c;
        c.aOverDx = aOverDx;
        c.threads = threads;
        c.shiftCells = shift;
        const InclinedCrackResult r = runInclinedCrack(c);
        char text[160];
        std::snprintf(text, sizeof text,
                      "inclined 45° a/dx=%g shifted %.2f cell: K_I %+.2f / %+.2f%%, K_II %+.2f / %+.2f%% (start / end tip)",
                      aOverDx, shift, 100 * (r.KI[0] / r.KIreference - 1), 100 * (r.KI[1] / r.KIreference - 1),
                      100 * (r.KII[0] / r.KIIreference - 1), 100 * (r.KII[1] / r.KIIreference - 1));
        t.note(text);
    }
}

void inclinedCrack(Table& t, double aOverDx, int threads) {
    InclinedCrackCase c;
    c.aOverDx = aOverDx;
    c.threads = threads;
    const InclinedCrackResult r = runInclinedCrack(c);
    char name[96];
    for (int tip = 0; tip < 2; ++tip) {
        const char* which = tip == 0 ? "start" : "end";
        std::snprintf(name, sizeof name, "inclined 45° a/dx=%g, %s tip: K_I", aOverDx, which);
        t.relative(name, r.KI[tip], r.KIreference, 0.05);
        std::snprintf(name, sizeof name, "inclined 45° a/dx=%g, %s tip: K_II", aOverDx, which);
        t.relative(name, r.KII[tip], r.KIIreference, 0.05);
        std::snprintf(name, sizeof name, "inclined 45° a/dx=%g, %s tip: K_II/K_I", aOverDx, which);
        t.relative(name, r.KII[tip] / r.KI[tip], 1.0, 0.05);
        std::snprintf(name, sizeof name, "inclined 45° a/dx=%g, %s tip: first kink (°)", aOverDx, which);
        t.absolute(name, r.kink[tip] / kDegree, -53.13, 3.0, "°");
    }
}

void drop(Table& t, int threads) {
    // A jello disk (E 50 Pa, so a few hundred substeps) of radius 5 m dropped from 5 m
    // (its bottom; the kernel reaches the ground's nodes from 1 m above it).
    Scene s;
    s.grid.dx = 0.5;
    s.gravity = Vec2(0, -9.81);
    s.materials.push_back(*materialPreset("jello"));
    s.materials[0].Kc = INFINITY;
    s.bodies.push_back(Body{Shape(CircleShape{Vec2(0, 10), 5}), 0, Vec2::Zero()});
    s.colliders.push_back(std::make_shared<HalfPlaneCollider>(Vec2(0, 0), Vec2(0, 1)));
    Solver2D solver(s);
    if (threads > 0) solver.setThreads(threads);
    const Totals t0 = totals(solver);
    solver.advance(0.25); // free flight: the disk has not reached the ground yet
    const Totals t1 = totals(solver);
    const Vec2 expected = t0.momentum + t0.mass * s.gravity * solver.time();
    t.absolute("drop: momentum in free flight, |Δp|/|p|", (t1.momentum - expected).norm() / expected.norm(), 0, 1e-10, "");
    double highest = t0.total();
    for (int k = 0; k < 40; ++k) {
        solver.advance(0.05);
        highest = std::max(highest, totals(solver).total());
    }
    const double dropEnergy = t0.mass * 9.81 * 5;
    t.absolute("drop: largest energy gain / drop energy", (highest - t0.total()) / dropEnergy, 0, 2e-3, "");
    t.check("drop: mass (kg/m), exactly conserved", totals(solver).mass, "== initial", totals(solver).mass == t0.mass);
}

} // namespace

int main(int argc, char** argv) {
    CLI::App app("Validation of the 2D MPM crack solver against fracture mechanics", "shatter-mpm-validate");
    bool quick = false, full = false, gridOnly = false, inclinedShifts = false;
    int threads = 0;
    app.add_flag("--quick", quick, "The CTest run: the coarsest resolution of each check (under a minute on one core)");
    app.add_flag("--full", full, "Also the fine resolutions (centre crack a/dx = 20, inclined crack a/dx = 16)");
    app.add_flag("--grid-offsets", gridOnly, "Only the crack-anywhere-on-the-grid rows (crack line and tip offsets)");
    app.add_flag("--inclined-shifts", inclinedShifts,
                 "Only the inclined crack (a/dx = 8) moved along itself by 0, 1/4, 1/2, 3/4 cell, as notes");
    app.add_option("--threads", threads, "Threads (default: all cores)")->check(CLI::PositiveNumber);
    app.failure_message([](const CLI::App* a, const CLI::Error& e) {
        return "shatter-mpm-validate: error: " + CLI::FailureMessage::simple(a, e);
    });
    CLI11_PARSE(app, argc, argv);
    if (quick && full) {
        std::cerr << "shatter-mpm-validate: error: --quick and --full exclude each other" << std::endl;
        return 1;
    }
    std::setvbuf(stdout, nullptr, _IOLBF, 0); // rows appear as they are measured, also in a log
    try {
        Table table;
        // (crack line, tips) past a grid line, in cells: every crack-line offset at every tip offset.
        std::vector<std::pair<double, double>> offsets;
        for (double line : {0.0, 0.25, 1.0 / 3, 0.5})
            for (double tip : {0.0, 0.25, 0.5, 0.75}) offsets.push_back({line, tip});
        const std::vector<double> runningLines{0.0, 0.25, 1.0 / 3, 0.5}; // crack lines of the running crack
        if (inclinedShifts) {
            inclinedCrackShifted(table, 8, threads);
            return 0;
        }
        if (gridOnly) {
            finiteElementReference(table);
            anywhereOnGrid(table, offsets, threads);
            runningCrack(table, runningLines, threads);
            std::printf("\n%s: %d row(s) failed\n", table.failed() ? "FAILED" : "passed", table.failed());
            return table.failed() ? 1 : 0;
        }
        finiteElementReference(table);
        exactField(table);
        drop(table, threads);
        // λ = 0.2 needs the widest plate (180,000 particles at a/dx = 10): not in the quick run.
        centreCrack(table, quick ? std::vector<double>{0.4, 0.6} : std::vector<double>{0.2, 0.4, 0.6}, 10, 0.05,
                    threads);
        if (full) centreCrack(table, {0.2, 0.4, 0.6}, 20, 0.03, threads);
        offGrid(table, quick ? std::vector<double>{0.125, 0.875} : std::vector<double>{0.125, 0.375, 0.625, 0.875},
                threads);
        inclinedCrack(table, 8, threads);
        if (full) inclinedCrack(table, 16, threads);
        if (!quick) anywhereOnGrid(table, offsets, threads);
        if (!quick) runningCrack(table, runningLines, threads);
        std::printf("\n%s: %d row(s) failed\n", table.failed() ? "FAILED" : "passed", table.failed());
        return table.failed() ? 1 : 0;
    } catch (const std::exception& e) {
        std::cerr << "shatter-mpm-validate: error: " << e.what() << std::endl;
        return 1;
    }
}
