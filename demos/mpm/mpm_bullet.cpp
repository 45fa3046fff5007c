// shatter-mpm-bullet: the 2D crack solver as a sidecar of a Bullet world. A block of snow
// (MPM) falls onto a tilted static Bullet box, slides down it and lands on
// the Bullet ground plane. Both Bullet objects reach the solver only through
// shatter::MpmCollider (shatter/bullet_ext/mpm/MpmCollider.h): the MPM plane is world
// z = 0, MPM x, y = world x, y.
//
//   shatter-mpm-bullet [--out DIR] [--frames N] [--fps F] [--tilt DEG] [--friction MU]
//                      [--threads T] [--quiet] [--png-every N] [--png-size WxH]
//
// Output in DIR (default out/mpm_bullet), as shatter-mpm writes it: tips.csv,
// particles_NNNN.csv, cracks_NNNN.csv (see MpmOutput.h) and frame_NNNN.png: particles
// coloured by their largest principal stress (blue compression, red tension), the Bullet
// box and ground in grey. The block slides down the box (friction 0.25, below tan 20°), drops
// off its lower end and stops on the ground (friction 0.6). Errors: "shatter-mpm-bullet: error: ..." and exit code 1.
#include <shatter/bullet_ext/mpm/MpmCollider.h>
#include "demos/mpm/MpmOutput.h"
#include <shatter/plugin/mpm/Diagnostics.h>
#include <shatter/plugin/mpm/Solver2D.h>

#include <CLI/CLI.hpp>
#include <btBulletDynamicsCommon.h>
#include <cairo.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <iostream>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <unistd.h>
#include <vector>

namespace {

using shatter::mpm::Vec2;
const char* kProgram = "shatter-mpm-bullet";

struct Options {
    std::string out = "out/mpm_bullet";
    int frames = 72;
    double fps = 24;
    double tiltDegrees = 20;
    double friction = 0.25;
    // One thread by default: this scene has a few hundred particles, and a team of threads
    // would spend more at the solver's barriers than it gains (more so on a busy machine).
    int threads = 1;
    bool quiet = false;
    int pngEvery = 1;
    std::string pngSize = "1000x800";
};

// The Bullet side, as an application would have it: its own world, a ground plane and a
// static box tilted about z, half extents 0.6 × 0.08 × 0.5 m, centre (0, 0.45, 0).
struct BulletScene {
    btDefaultCollisionConfiguration config;
    btCollisionDispatcher dispatcher{&config};
    btDbvtBroadphase broadphase;
    btSequentialImpulseConstraintSolver solver;
    btDiscreteDynamicsWorld world{&dispatcher, &broadphase, &solver, &config};
    btStaticPlaneShape groundShape{btVector3(0, 1, 0), 0};
    btBoxShape boxShape{btVector3(0.6f, 0.08f, 0.5f)};
    btRigidBody ground{0, nullptr, &groundShape};
    btRigidBody box{0, nullptr, &boxShape};

    explicit BulletScene(double tilt) {
        world.setGravity(btVector3(0, -9.81f, 0));
        box.setWorldTransform(btTransform(btQuaternion(btVector3(0, 0, 1), btScalar(tilt)), btVector3(0, 0.45f, 0)));
        world.addRigidBody(&ground);
        world.addRigidBody(&box);
    }
    ~BulletScene() {
        world.removeRigidBody(&box);
        world.removeRigidBody(&ground);
    }
};

// The MPM side: a 0.3 m × 0.2 m block of snow (the source's snow preset: E 140 kPa, ν 0.2,
// ρ 400, Stomakhin's elasto-plastic model, which dents instead of bouncing), dx 2.5 cm,
// 2 × 2 particles per cell, released 0.2 m above the box's upper half.
shatter::mpm::Scene blockScene() {
    shatter::mpm::Scene s;
    s.source = "shatter-mpm-bullet block";
    s.grid.dx = 0.025;
    s.grid.ppc = 2;
    s.gravity = Vec2(0, -9.81);
    s.materials.push_back(*shatter::mpm::materialPreset("snow"));
    s.bodies.push_back({shatter::mpm::Shape(shatter::mpm::RectShape{Vec2(0.1, 0.85), Vec2(0.4, 1.05)}), 0, Vec2::Zero()});
    return s;
}

// A fixed view of the region where things happen, in a width × height picture.
class Picture {
public:
    Picture(int width, int height) : width_(width), height_(height) {
        const Vec2 lo(-1.4, -0.1), hi(0.8, 1.15);
        centre_ = 0.5 * (lo + hi);
        scale_ = std::min(width / (hi.x() - lo.x()), (height - kTitle) / (hi.y() - lo.y()));
    }

    void write(const std::filesystem::path& path, const shatter::mpm::Solver2D& solver, const BulletScene& bullet,
               const shatter::MpmCollider& boxView, const std::string& title) const {
        std::unique_ptr<cairo_surface_t, void (*)(cairo_surface_t*)> surface(
            cairo_image_surface_create(CAIRO_FORMAT_RGB24, width_, height_), cairo_surface_destroy);
        std::unique_ptr<cairo_t, void (*)(cairo_t*)> cr(cairo_create(surface.get()), cairo_destroy);
        cairo_t* c = cr.get();
        cairo_set_source_rgb(c, 1, 1, 1);
        cairo_paint(c);

        // Bullet objects: the ground below y = 0 and the box's cross-section with the plane.
        cairo_set_source_rgb(c, 0.62, 0.64, 0.68);
        const double far = 100;
        polygon(c, {Vec2(-far, 0), Vec2(far, 0), Vec2(far, -far), Vec2(-far, -far)});
        const btVector3 h = bullet.boxShape.getHalfExtentsWithMargin();
        const btTransform& t = bullet.box.getWorldTransform();
        polygon(c, {boxView.toPlane(t * btVector3(-h.x(), -h.y(), 0)), boxView.toPlane(t * btVector3(h.x(), -h.y(), 0)),
                    boxView.toPlane(t * btVector3(h.x(), h.y(), 0)), boxView.toPlane(t * btVector3(-h.x(), h.y(), 0))});

        // Particles, coloured by σ₁ on a symmetric scale from the 99th percentile of |σ₁|.
        const auto& P = solver.particles();
        std::vector<double> s1(P.size()), magnitude(P.size());
        for (size_t p = 0; p < P.size(); ++p) {
            const shatter::mpm::Mat2 s = solver.cauchyStress(p);
            s1[p] = 0.5 * (s(0, 0) + s(1, 1)) + std::hypot(0.5 * (s(0, 0) - s(1, 1)), s(0, 1));
            magnitude[p] = std::abs(s1[p]);
        }
        const size_t k = std::min(magnitude.size() - 1, size_t(0.99 * double(magnitude.size())));
        std::nth_element(magnitude.begin(), magnitude.begin() + long(k), magnitude.end());
        const double stressScale = magnitude[k] > 0 ? magnitude[k] : 1.0;
        const double side = std::max(1.0, solver.particleSpacing() * scale_);
        cairo_set_antialias(c, CAIRO_ANTIALIAS_NONE); // neighbouring squares meet without seams
        for (size_t p = 0; p < P.size(); ++p) {
            const double v = std::clamp(s1[p] / stressScale, -1.0, 1.0), a = std::abs(v);
            if (v < 0)
                cairo_set_source_rgb(c, 0.97 - 0.82 * a, 0.97 - 0.62 * a, 0.97 - 0.12 * a);
            else
                cairo_set_source_rgb(c, 0.97 - 0.12 * a, 0.97 - 0.82 * a, 0.97 - 0.85 * a);
            const Vec2 q = pixels(P.x[p]);
            cairo_rectangle(c, q.x() - 0.5 * side, q.y() - 0.5 * side, side, side);
            cairo_fill(c);
        }
        cairo_set_antialias(c, CAIRO_ANTIALIAS_DEFAULT);

        cairo_set_source_rgb(c, 0.13, 0.15, 0.18);
        cairo_select_font_face(c, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
        cairo_set_font_size(c, 15);
        cairo_move_to(c, 12, 25);
        char scale[96];
        std::snprintf(scale, sizeof scale, "   ·   σ₁ scale ±%.3g Pa   ·   grey: Bullet objects", stressScale);
        cairo_show_text(c, (title + scale).c_str());
        cairo_surface_flush(surface.get());
        if (cairo_surface_write_to_png(surface.get(), path.string().c_str()) != CAIRO_STATUS_SUCCESS)
            throw std::runtime_error(path.string() + ": cannot write the PNG");
    }

private:
    static constexpr int kTitle = 40; // pixels at the top for the title line

    Vec2 pixels(const Vec2& p) const {
        return Vec2(0.5 * width_ + (p.x() - centre_.x()) * scale_,
                    kTitle + 0.5 * (height_ - kTitle) - (p.y() - centre_.y()) * scale_);
    }
    void polygon(cairo_t* c, const std::vector<Vec2>& pts) const {
        for (size_t i = 0; i < pts.size(); ++i) {
            const Vec2 q = pixels(pts[i]);
            i == 0 ? cairo_move_to(c, q.x(), q.y()) : cairo_line_to(c, q.x(), q.y());
        }
        cairo_close_path(c);
        cairo_fill(c);
    }

    int width_, height_;
    Vec2 centre_;
    double scale_;
};

int run(const Options& o, bool progress) {
    int width = 0, height = 0;
    if (std::sscanf(o.pngSize.c_str(), "%dx%d", &width, &height) != 2 || width < 64 || height < 64 || width > 8192 ||
        height > 8192)
        throw std::invalid_argument("--png-size: expected WIDTHxHEIGHT from 64 to 8192 pixels, got '" + o.pngSize + "'");

    BulletScene bullet(o.tiltDegrees * std::numbers::pi / 180);
    shatter::mpm::Solver2D solver(blockScene());
    if (o.threads > 0) solver.setThreads(o.threads);
    // The Bullet objects as obstacles, seen through their signed distance.
    auto box = std::make_shared<shatter::MpmCollider>(bullet.box, btTransform::getIdentity(), o.friction);
    // The ground holds the block with friction 0.6 once it has slid off the box.
    auto ground = std::make_shared<shatter::MpmCollider>(bullet.ground, btTransform::getIdentity(), 0.6);
    solver.addCollider(box);
    solver.addCollider(ground);

    shatter::mpm::demo::MpmOutput output(o.out, o.frames);
    const Picture picture(width, height);
    auto writeFrame = [&](int frame) {
        output.writeFrame(frame, solver);
        if (o.pngEvery > 0 && frame % o.pngEvery == 0) {
            char title[160];
            std::snprintf(title, sizeof title, "%s  ·  frame %d/%d  ·  t = %.3f s", kProgram, frame, o.frames, solver.time());
            picture.write(output.dir() / shatter::mpm::demo::frameFileName("frame", frame, o.frames, "png"), solver,
                          bullet, *box, title);
        }
    };
    solver.analyseTips();
    writeFrame(0);
    const double frameDt = 1.0 / o.fps;
    const auto start = std::chrono::steady_clock::now();
    for (int frame = 1; frame <= o.frames; ++frame) {
        // The application's loop: Bullet steps, the colliders read the new poses (these two
        // are static, so nothing changes; a moving body would drive the material), then the
        // sidecar advances by the same time.
        bullet.world.stepSimulation(btScalar(frameDt), 4, btScalar(1.0 / 240));
        box->update();
        ground->update();
        solver.advance(frameDt);
        writeFrame(frame);
        if (progress && !o.quiet)
            std::fprintf(stderr, "\r%s: frame %d/%d  t = %.3f s  %ld substeps   ", kProgram, frame, o.frames,
                         solver.time(), solver.substeps());
    }
    if (progress && !o.quiet) std::fprintf(stderr, "\n");
    if (!o.quiet) {
        const auto t = shatter::mpm::totals(solver);
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        std::printf("%s: %d frames, %.3f s simulated, %zu particles, %ld substeps, %.1f s wall clock\n", kProgram,
                    o.frames, solver.time(), solver.particles().size(), solver.substeps(), seconds);
        std::printf("  block centre of mass (%.3f, %.3f) m, velocity (%.3f, %.3f) m/s\n", t.centreOfMass.x(),
                    t.centreOfMass.y(), t.momentum.x() / t.mass, t.momentum.y() / t.mass);
        std::printf("  output    %s\n", output.dir().string().c_str());
    }
    return 0;
}

} // namespace

int main(int argc, char** argv) {
    std::signal(SIGPIPE, SIG_IGN);
    Options o;
    CLI::App app{"MPM block on a tilted Bullet box: the 2D crack solver as a sidecar of a Bullet world", kProgram};
    app.add_option("--out", o.out, "Output directory, created with its parents")->capture_default_str();
    app.add_option("--frames", o.frames, "Frames to simulate and write")->check(CLI::Range(1, 100000))->capture_default_str();
    app.add_option("--fps", o.fps, "Frames per second")->check(CLI::Range(1.0, 10000.0))->capture_default_str();
    app.add_option("--tilt", o.tiltDegrees, "Tilt of the Bullet box about z, degrees")
        ->check(CLI::Range(-60.0, 60.0))
        ->capture_default_str();
    app.add_option("--friction", o.friction, "Coulomb friction of the material on the tilted box")
        ->check(CLI::Range(0.0, 10.0))
        ->capture_default_str();
    app.add_option("--threads", o.threads, "Threads for the MPM loops (0: all cores)")
        ->check(CLI::Range(0, 1024))
        ->capture_default_str();
    app.add_flag("--quiet,-q", o.quiet, "No progress line and no final report");
    app.add_option("--png-every", o.pngEvery, "Write frame_NNNN.png every N frames (0: none)")
        ->check(CLI::Range(0, 100000))
        ->capture_default_str();
    app.add_option("--png-size", o.pngSize, "Picture size in pixels, WxH")->capture_default_str();
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e);
    }
    try {
        return run(o, isatty(STDERR_FILENO) == 1);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "%s: error: %s\n", kProgram, e.what());
        return 1;
    }
}
