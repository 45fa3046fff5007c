#include "demos/runner/DemoRunner.h"

#include "demos/runner/FrameWriter.h"
#include "demos/runner/GltfWriter.h"
#include "demos/runner/OutputDirectory.h"
#include "demos/runner/PngRenderer.h"
#include "demos/runner/ProgressLine.h"
#include "demos/runner/RunRecording.h"
#include "demos/runner/StoryBoard.h"
#include "demos/runner/Summary.h"

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <optional>
#include <set>

namespace shatter::demo {

namespace {

double millisecondsSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

// Steps one frame of exactly `substeps` fixed steps and returns its wall-clock milliseconds
// (what the progress line and the summary report).
double timedStep(btDiscreteDynamicsWorld& world, const RunOptions& o) {
    // Bullet takes int(accumulated time / fixed step) steps. With 1/fps in single precision
    // that ratio can land just below K, so one frame would take K-1 steps and a later one
    // catch up. A frame time a hair above K fixed steps always gives K; the excess piles up
    // until a frame asks for K+1, which maxSubSteps = K clamps, dropping it.
    const btScalar fixed = btScalar(o.substepSeconds());
    const btScalar frame = fixed * btScalar(o.substeps) * btScalar(1 + 1e-5);
    const auto start = std::chrono::steady_clock::now();
    world.stepSimulation(frame, o.substeps, fixed);
    return millisecondsSince(start);
}

std::string formatted(const char* format, auto... values) {
    char text[256];
    std::snprintf(text, sizeof text, format, values...);
    return text;
}

int objectCount(const std::vector<NamedMesh>& meshes) {
    return int(std::count_if(meshes.begin(), meshes.end(), [](const NamedMesh& m) { return !m.ground; }));
}

std::string bodyCount(int n) { return std::to_string(n) + (n == 1 ? " body" : " bodies"); }

// A body whose coordinates went non-finite has blown up; say so once per body instead of
// silently writing "nan" into every later frame.
class BlowUpWatch {
public:
    std::vector<std::string> newlyBroken(const std::vector<NamedMesh>& meshes) {
        std::vector<std::string> names;
        for (const NamedMesh& m : meshes) {
            if (reported_.count(m.name)) continue;
            const bool finite = std::all_of(m.mesh.positions.begin(), m.mesh.positions.end(),
                                            [](const Eigen::Vector3d& p) { return p.allFinite(); });
            if (!finite && reported_.insert(m.name).second) names.push_back(m.name);
        }
        return names;
    }

private:
    std::set<std::string> reported_;
};

// The optional frame_NNNN.png pictures: every `every` frames, all through one camera (set
// at the first picture) so that they play as a film.
class PictureSequence {
public:
    PictureSequence(std::filesystem::path dir, int every, int frameCount)
        : dir_(std::move(dir)), every_(every), frameCount_(frameCount) {}

    void maybeWrite(int frame, const std::vector<NamedMesh>& meshes, const Picture& picture) {
        if (every_ <= 0 || frame % every_ != 0) return;
        if (!camera_) camera_ = frameScene(meshes, picture);
        renderPng(meshes, *camera_, picture, dir_ / frameFileName(frame, frameCount_, "png"));
        if (written_++ == 0) first_ = frame;
        last_ = frame;
    }
    int written() const { return written_; }
    int first() const { return first_; }
    int last() const { return last_; }

private:
    std::filesystem::path dir_;
    int every_, frameCount_;
    std::optional<Camera> camera_;
    int written_ = 0, first_ = 0, last_ = 0;
};

struct Written {
    OutputDirectory dir;
    int objFrames = 0;
    int pngFrames = 0;
    int firstPng = 0, lastPng = 0;
    std::optional<FirstChange> change;
    std::optional<GltfStats> gltf;
    double recordMs = 0; // keeping every frame for the story and scene.glb, whole run
    double gltfMs = 0;   // writing scene.glb
};

void printReport(std::ostream& out, const std::string& program, const RunOptions& o, const Written& w, int bodies,
                 double medianMs) {
    const auto& dir = w.dir.path;
    out << formatted("%s: %d frames, %.2f s simulated, %s, %.2f ms/frame (median step)\n", program.c_str(),
                     o.frames, o.frames / o.fps, bodyCount(bodies).c_str(), medianMs);
    out << "  output    " << dir.string() << "\n";
    out << "  frames    " << w.objFrames << " OBJ files, " << frameFileName(1, o.frames, "obj") << " to "
        << frameFileName(o.frames, o.frames, "obj") << "\n";
    if (w.pngFrames > 0)
        out << "  pictures  " << w.pngFrames << " PNG files, " << frameFileName(w.firstPng, o.frames, "png") << " to "
            << frameFileName(w.lastPng, o.frames, "png") << "\n";
    out << "  summary   " << (dir / "summary.json").string() << "\n";
    out << "  picture   " << (dir / "final.png").string() << "\n";
    out << "  story     " << (dir / "story.png").string() << "  (six moments"
        << (w.change ? formatted("; %s at t = %.2f s", w.change->what.c_str(), w.change->frame / o.fps) : std::string())
        << ")\n";
    if (w.gltf)
        out << "  scene     " << (dir / "scene.glb").string()
            << formatted("  (%.1f MB; keeping the frames %.2f ms/frame, writing %.0f ms; Blender: File > Import > "
                         "glTF 2.0, then play)",
                         double(w.gltf->bytes) / 1e6, w.recordMs / o.frames, w.gltfMs)
            << "\n";
    if (w.gltf) out << "  viewer    scripts/view.sh " << dir.string() << "  (plays scene.glb in the browser)\n";
    if (w.dir.staleFramesRemoved > 0)
        out << "  (cleared " << w.dir.staleFramesRemoved << " frame files of an earlier run first)\n";
}

} // namespace

DemoRunner::DemoRunner(std::string name, std::string description)
    : name_(std::move(name)), description_(std::move(description)), program_("shatter-" + name_),
      app_(description_, program_) {
    options_.out = "out/" + name_;
    addRunOptions(app_, options_);
    // CLI11's own message and exit code, under the same prefix as every other error.
    app_.failure_message([this](const CLI::App* app, const CLI::Error& e) {
        return program_ + ": error: " + CLI::FailureMessage::simple(app, e);
    });
}

void DemoRunner::setStreams(std::ostream& out, std::ostream& err) {
    out_ = &out;
    err_ = &err;
}

int DemoRunner::run(int argc, const char* const* argv, const Setup& setup) {
    // A demo piped into `head` must end with an exit code, not be killed by SIGPIPE; a write
    // to a closed pipe then just fails. Only the process entry point does this, not tests.
    std::signal(SIGPIPE, SIG_IGN);
    std::vector<std::string> args;
    for (int i = 1; i < argc; ++i) args.emplace_back(argv[i]);
    return run(std::move(args), setup);
}

int DemoRunner::run(std::vector<std::string> args, const Setup& setup) {
    try {
        std::reverse(args.begin(), args.end()); // CLI11 takes the vector last-argument-first
        app_.parse(args);
    } catch (const CLI::ParseError& e) {
        return app_.exit(e, *out_, *err_);
    } catch (const std::exception& e) {
        *err_ << program_ << ": error: " << e.what() << std::endl;
        return 1;
    }
    try {
        return simulate(setup);
    } catch (const std::exception& e) {
        *err_ << program_ << ": error: " << e.what() << std::endl;
    } catch (...) {
        *err_ << program_ << ": error: unknown exception" << std::endl;
    }
    return 1;
}

int DemoRunner::simulate(const Setup& setup) {
    const RunOptions& o = options_;
    // The directory first: a run that cannot write its output fails before any work.
    Written written;
    written.dir = prepareOutputDirectory(o.out);
    Scene scene(o.seed);
    setup(scene);

    FrameWriter objWriter(written.dir.path, o.frames);
    const bool showProgress = !o.quiet && err_ == &std::cerr && ProgressLine::stderrIsTerminal();
    ProgressLine progress(*err_, program_, o.frames, showProgress);
    StepTimes times;
    EventCounts eventCounts;
    FrameCounts frameCounts;
    BlowUpWatch blowUps;
    PictureSequence pictures(written.dir.path, o.pngEvery, o.frames);
    std::vector<NamedMesh> meshes;
    RunRecording recording;
    auto picture = [&](int frame) {
        return Picture{o.pngWidth, o.pngHeight, program_,
                       formatted("frame %d/%d  ·  t = %.2f s  ·  %s", frame, o.frames, frame / o.fps,
                                 bodyCount(objectCount(meshes)).c_str())};
    };

    for (int i = 1; i <= o.frames; ++i) {
        times.ms.push_back(timedStep(scene.world(), o));
        const std::vector<Event> events = scene.plugin().takeEvents();
        for (const Event& e : events) {
            ++eventCounts[toString(e.type)];
            if (const auto words = changeWords(e.type); words && !written.change) written.change = FirstChange{i, *words};
        }
        for (const std::string& warning : scene.plugin().takeWarnings()) {
            progress.finish();
            *err_ << program_ << ": warning: " << warning << std::endl;
        }
        scene.notifyFrame(Frame{i, o.frames, i / o.fps, events});

        meshes = scene.meshes();
        frameCounts.bodies.push_back(objectCount(meshes));
        frameCounts.events.push_back(int(events.size()));
        for (const std::string& name : blowUps.newlyBroken(meshes)) {
            progress.finish();
            *err_ << program_ << ": warning: '" << name << "' has non-finite coordinates from frame " << i
                  << " on (the simulation blew up)" << std::endl;
        }
        objWriter.write(i, meshes, formatted("%s frame %d/%d t=%.6f s seed %llu", program_.c_str(), i, o.frames,
                                             i / o.fps, (unsigned long long)o.seed));
        pictures.maybeWrite(i, meshes, picture(i));
        for (const Scene::PictureRequest& request : scene.takePictureRequests()) {
            const Picture asked = picture(i);
            renderPng(meshes, frameScene(meshes, asked, request.focus), asked, written.dir.path / request.file);
        }
        const auto recordStart = std::chrono::steady_clock::now();
        recording.add(i, meshes, int(events.size()));
        written.recordMs += millisecondsSince(recordStart);
        progress.update(i, times.ms.back());
    }
    progress.finish();
    written.objFrames = objWriter.written();
    written.pngFrames = pictures.written();
    written.firstPng = pictures.first();
    written.lastPng = pictures.last();

    const Picture last = picture(o.frames);
    renderPng(meshes, frameScene(meshes, last), last, written.dir.path / "final.png");
    writeStory(recording, o.fps, written.change,
               Picture{o.pngWidth, o.pngHeight, program_,
                       formatted("%d frames  ·  %.2f s simulated", o.frames, o.frames / o.fps)},
               written.dir.path / "story.png");
    if (o.gltf) {
        const auto start = std::chrono::steady_clock::now();
        written.gltf = writeGltf(recording, o.fps, written.dir.path / "scene.glb");
        written.gltfMs = millisecondsSince(start);
    }
    const auto summary = buildSummary(name_, description_, o, scene, times, eventCounts, frameCounts);
    writeFile(written.dir.path / "summary.json", summaryText(summary));
    if (!o.quiet) printReport(*out_, program_, o, written, objectCount(meshes), times.median());
    return 0;
}

} // namespace shatter::demo
