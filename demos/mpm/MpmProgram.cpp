#include "demos/mpm/MpmProgram.h"

#include "demos/mpm/MpmOutput.h"
#include "demos/mpm/MpmPicture.h"
#include <shatter/plugin/common/InputError.h>
#include <shatter/plugin/mpm/SceneBudget.h>
#include <shatter/plugin/mpm/SceneFile.h>

#include <CLI/CLI.hpp>

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <optional>

namespace shatter::mpm::demo {

namespace {

const char* kProgram = "shatter-mpm";

struct Options {
    std::string scene;
    std::string out;
    std::optional<int> frames;
    std::optional<std::uint64_t> seed;
    int threads = 0; // 0: all cores
    bool quiet = false;
    int pngEvery = 1;
    int pngWidth = 1000, pngHeight = 800;
    SceneLimits limits;
};

template <class T>
bool parseWhole(const std::string& text, T& value) {
    const char* end = text.data() + text.size();
    const auto r = std::from_chars(text.data(), end, value);
    return r.ec == std::errc() && r.ptr == end;
}

// Decimal integers only (CLI11's own conversion accepts "0x10" and "010" as octal).
std::string formatted(const char* pattern, double a, double b = 0, double c = 0) {
    char text[256];
    std::snprintf(text, sizeof text, pattern, a, b, c);
    return text;
}

// A positive limit, e.g. --max-particles 2e7; `unit` scales it (1e9 for gigabytes).
std::function<void(const std::string&)> limit(const char* name, double unit, double& target) {
    return [name, unit, &target](const std::string& s) {
        double v = 0;
        if (!parseWhole(s, v) || !std::isfinite(v) || v <= 0)
            throw CLI::ValidationError(name, "expected a number > 0, got '" + s + "'");
        target = v * unit;
    };
}

std::function<void(const std::string&)> integer(const char* name, int minimum, int& target) {
    return [name, minimum, &target](const std::string& s) {
        long long v = 0;
        if (!parseWhole(s, v) || v < minimum || v > 1'000'000'000)
            throw CLI::ValidationError(name, "expected an integer >= " + std::to_string(minimum) + ", got '" + s + "'");
        target = int(v);
    };
}

void addOptions(CLI::App& app, Options& o) {
    app.add_option("scene", o.scene, "Scene file (JSON)")->required()->type_name("SCENE.json");
    app.add_option("--out", o.out, "Output directory, created with its parents (default: out/<scene name>)")
        ->type_name("DIR");
    app.add_option_function<std::string>("--frames", [&o](const std::string& s) {
           int f = 0;
           integer("--frames", 1, f)(s);
           o.frames = f;
       }, "Frames to write (default: the scene's time.end / time.frame)")
        ->type_name("N");
    app.add_option_function<std::string>("--seed", [&o](const std::string& s) {
           std::uint64_t v = 0;
           if (!parseWhole(s, v)) throw CLI::ValidationError("--seed", "expected an unsigned integer, got '" + s + "'");
           o.seed = v;
       }, "Seed of the particle jitter (default: the scene's \"seed\", else 1)")
        ->type_name("S");
    app.add_option_function<std::string>("--threads", integer("--threads", 1, o.threads),
                                         "Threads for the particle and grid loops (default: all cores)")
        ->type_name("T");
    app.add_flag("--quiet,-q", o.quiet, "No progress line and no final report");
    app.add_option_function<std::string>("--png-every", integer("--png-every", 0, o.pngEvery),
                                         "Write frame_NNNN.png every N frames (0: none)")
        ->type_name("N")
        ->default_str("1");
    app.add_option_function<std::string>(
           "--png-size",
           [&o](const std::string& s) {
               const auto x = s.find_first_of("xX");
               int w = 0, h = 0;
               if (x == std::string::npos || !parseWhole(s.substr(0, x), w) || !parseWhole(s.substr(x + 1), h) ||
                   w < 64 || h < 64 || w > 8192 || h > 8192)
                   throw CLI::ValidationError("--png-size", "expected WIDTHxHEIGHT from 64 to 8192 pixels, got '" + s + "'");
               o.pngWidth = w;
               o.pngHeight = h;
           },
           "Picture size in pixels")
        ->type_name("WxH")
        ->default_str("1000x800");
    // The scene's cost is estimated before anything runs (SceneBudget.h); beyond these it is an error.
    app.add_option_function<std::string>("--max-particles", limit("--max-particles", 1, o.limits.maxParticles),
                                         "Largest particle (and crack point) count to accept")
        ->type_name("N")
        ->default_str(formatted("%g", o.limits.maxParticles));
    app.add_option_function<std::string>("--max-substeps", limit("--max-substeps", 1, o.limits.maxSubsteps),
                                         "Largest substep count to accept (the run's length / the CFL step at the start)")
        ->type_name("N")
        ->default_str(formatted("%g", o.limits.maxSubsteps));
    app.add_option_function<std::string>("--max-particle-steps",
                                         limit("--max-particle-steps", 1, o.limits.maxParticleSteps),
                                         "Largest particle count x substep count to accept (the run's work)")
        ->type_name("N")
        ->default_str(formatted("%g", o.limits.maxParticleSteps));
    app.add_option_function<std::string>("--max-memory", limit("--max-memory", 1e9, o.limits.maxMemory),
                                         "Largest estimated memory to accept, in GB")
        ->type_name("GB")
        ->default_str(formatted("%g", o.limits.maxMemory / 1e9));
}

class Progress {
public:
    Progress(std::ostream& err, bool enabled, int frames) : err_(err), enabled_(enabled), frames_(frames) {}
    void update(int frame, double time, long substeps, double seconds) {
        if (!enabled_) return;
        char text[200];
        std::snprintf(text, sizeof text, "\r%s: frame %d/%d  t = %.4g s  %ld substeps  %.2f s/frame   ", kProgram,
                      frame, frames_, time, substeps, seconds);
        err_ << text << std::flush;
        drawn_ = true;
    }
    void finish() {
        if (drawn_) err_ << '\n' << std::flush;
        drawn_ = false;
    }

private:
    std::ostream& err_;
    bool enabled_;
    int frames_;
    bool drawn_ = false;
};

void report(std::ostream& out, const Solver2D& solver, const MpmOutput& output, int frames, double seconds,
            bool pictures) {
    out << kProgram << ": " << frames << " frames, " << formatted("%.4g s simulated, ", solver.time())
        << solver.particles().size() << " particles, " << solver.substeps() << " substeps, "
        << formatted("%.1f s wall clock\n", seconds);
    out << "  output    " << output.dir().string() << "\n";
    out << "  tips      " << (output.dir() / "tips.csv").string() << "\n";
    out << "  frames    " << frameFileName("particles", 0, frames, "csv") << ", " << frameFileName("cracks", 0, frames, "csv")
        << (pictures ? ", " + frameFileName("frame", 0, frames, "png") : std::string()) << " ... "
        << frameFileName("particles", frames, frames, "csv") << "\n";
    out << "  paraview  " << (output.dir() / "mpm.pvd").string() << "  (particles and cracks, .vtp per frame)\n";
    for (const TipResult& t : solver.tips())
        out << formatted("  crack %g ", t.crack) << (t.tip == 0 ? "start" : "end  ")
            << formatted(" at (%.4g, %.4g)", t.position.x(), t.position.y())
            << formatted("  J %.4g J/m²  K_I %.4g  K_II %.4g Pa√m", t.J, t.KI, t.KII)
            << formatted("  θ %.1f°\n", t.theta * 180 / M_PI);
}

// The run's frame count: --frames, else time.end / time.frame, which the limits have bounded
// by --max-substeps (each frame takes a substep); beyond an int it is an error, not a wrap.
int frameCount(const Options& o, const Scene& scene) {
    if (o.frames) return *o.frames;
    const double frames = std::ceil(scene.time.end / scene.time.frame - 1e-9);
    if (!(frames <= 1e9))
        throw InputError(scene.source + ": time.end / time.frame is " + formatted("%.3g", frames) +
                         " frames, more than 1e9");
    return std::max(1, int(frames));
}

void reportEstimate(std::ostream& out, const SceneEstimate& e) {
    out << kProgram << ": about " << formatted("%.3g particles, %.3g grid nodes, %.2g GB; ", e.particles, e.gridNodes, e.memory / 1e9)
        << formatted("CFL step %.3g s at the start, about %.3g substeps\n", e.firstStep, e.substeps) << std::flush;
}

int simulate(const Options& o, std::ostream& out, std::ostream& err, bool progressAllowed) {
    Scene scene = loadScene(o.scene);
    if (o.seed) scene.seed = *o.seed;
    // With --frames the run ends after those frames: that is the length the limits apply to.
    if (o.frames) scene.time.end = *o.frames * scene.time.frame;
    const SceneEstimate estimate = estimateScene(scene);
    checkSceneLimits(scene, estimate, o.limits);
    const int frames = frameCount(o, scene);
    if (!o.quiet) reportEstimate(out, estimate);
    const std::string dir = o.out.empty() ? "out/" + std::filesystem::path(o.scene).stem().string() : o.out;
    Solver2D solver(scene, o.limits);
    for (const std::string& w : solver.warnings()) err << kProgram << ": warning: " << w << std::endl;
    if (o.threads > 0) solver.setThreads(o.threads);
    MpmOutput output(dir, frames);
    const MpmPicture picture(solver, o.pngWidth, o.pngHeight);
    auto writeFrame = [&](int frame) {
        output.writeFrame(frame, solver);
        if (o.pngEvery > 0 && frame % o.pngEvery == 0)
            picture.write(output.dir() / frameFileName("frame", frame, frames, "png"), solver,
                          std::filesystem::path(o.scene).filename().string() +
                              formatted("  ·  frame %.0f/%.0f  ·  t = %.4g s", frame, frames, solver.time()));
    };
    solver.analyseTips();
    writeFrame(0);
    Progress progress(err, progressAllowed && !o.quiet, frames);
    const auto start = std::chrono::steady_clock::now();
    auto last = start;
    for (int frame = 1; frame <= frames; ++frame) {
        // A slow frame shows its substeps as they go, at most twice a second.
        auto shown = std::chrono::steady_clock::now();
        solver.advance(scene.time.frame, [&] {
            const auto now = std::chrono::steady_clock::now();
            if (now - shown < std::chrono::milliseconds(500)) return;
            shown = now;
            progress.update(frame - 1, solver.time(), solver.substeps(), std::chrono::duration<double>(now - last).count());
        });
        writeFrame(frame);
        const auto now = std::chrono::steady_clock::now();
        progress.update(frame, solver.time(), solver.substeps(), std::chrono::duration<double>(now - last).count());
        last = now;
    }
    progress.finish();
    if (!o.quiet)
        report(out, solver, output, frames,
               std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), o.pngEvery > 0);
    return 0;
}

} // namespace

int runMpmProgram(const std::vector<std::string>& args, std::ostream& out, std::ostream& err, bool progressAllowed) {
    CLI::App app("2D crack propagation with the material point method and the J-integral", kProgram);
    Options o;
    addOptions(app, o);
    app.failure_message([](const CLI::App* a, const CLI::Error& e) {
        return std::string(kProgram) + ": error: " + CLI::FailureMessage::simple(a, e);
    });
    try {
        std::vector<std::string> reversed(args.rbegin(), args.rend()); // CLI11 parses last-first
        app.parse(reversed);
    } catch (const CLI::ParseError& e) {
        // --help prints and succeeds; every other command-line error is exit code 1.
        return app.exit(e, out, err) == 0 ? 0 : 1;
    }
    try {
        return simulate(o, out, err, progressAllowed);
    } catch (const std::exception& e) {
        err << kProgram << ": error: " << e.what() << std::endl;
    } catch (...) {
        err << kProgram << ": error: unknown exception" << std::endl;
    }
    return 1;
}

} // namespace shatter::mpm::demo
