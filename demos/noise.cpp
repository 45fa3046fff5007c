// shatter-noise: the source's Fig. 4 (002 §4). Two identical walls side by side take the same
// impact: the left with uniform link strengths, the right with seeded 3D noise on its strengths
// and dynamic weakening around every break. The uniform wall cracks in the mesh's regular
// pattern; the noisy one breaks into irregular pieces.
#include <shatter/bullet_ext/lattice/LatticeBody.h>
#include "demos/LatticeDemo.h"
#include "demos/runner/DemoRunner.h"
#include <shatter/plugin/common/InputError.h>
#include <shatter/plugin/lattice/TetGenReader.h>
#include <shatter/plugin/lattice/TetGenerators.h>

#include <BulletCollision/CollisionShapes/btSphereShape.h>

#include <cmath>
#include <iostream>

namespace {

struct Options {
    shatter::demo::Ball ball{9.0, 300.0, 0.15};
    std::string tets;
    double strength = 0.0;    // Pa, when given: instead of adobe's
    double amplitude = 0.7;   // noise amplitude
    double scale = 0.15;      // m, noise feature size
    bool strengthGiven = false;
};

// 12 × 8 × 2 cells of 8 cm: 1,152 tets per wall (no jitter: the uniform wall is truly regular).
shatter::lattice::TetMesh wallMesh(const Options& o) {
    if (!o.tets.empty()) return shatter::lattice::readTetGen(o.tets);
    shatter::lattice::GeneratorOptions g;
    g.name = "wall";
    return shatter::lattice::tetBox({0.96, 0.64, 0.16}, {12, 8, 2}, g);
}

struct Wall {
    shatter::LatticeBody* body;
    std::string key;
};

Wall addWall(shatter::demo::Scene& scene, const shatter::lattice::TetMesh& mesh, const Options& o, bool noisy, double x) {
    double lowest = INFINITY, front = -INFINITY, top = -INFINITY;
    for (const auto& n : mesh.nodes) lowest = std::min(lowest, n.y()), front = std::max(front, n.z()), top = std::max(top, n.y());
    shatter::LatticeSettings s;
    s.name = noisy ? "noisy" : "uniform";
    s.seed = scene.seed();
    if (o.strengthGiven) s.material.strength = o.strength; // the body reports a bad one
    s.fixedTets = shatter::lattice::tetsWithFaceOnPlane(mesh, {0, 1, 0}, lowest, 1e-6);
    s.analysis.spreading.enabled = noisy;
    s.noise.enabled = noisy;
    s.noise.amplitude = o.amplitude;
    s.noise.scale = o.scale;
    const btTransform pose(btQuaternion::getIdentity(), btVector3(btScalar(x), btScalar(-lowest), 0));
    shatter::LatticeBody& body = scene.plugin().addLatticeBody(mesh, s, pose);
    const btVector3 at(btScalar(x), btScalar(0.5 * (top - lowest)), btScalar(front + o.ball.radius + 0.2));
    shatter::demo::launchBall(scene, o.ball, at, btVector3(0, 0, -1), noisy ? "ball_noisy" : "ball_uniform");
    return {&body, s.name};
}

} // namespace

int main(int argc, char** argv) {
    shatter::demo::DemoRunner runner("noise", "The same impact on a wall of uniform and of noisy, dynamically weakened strengths (source 002 Fig. 4).");
    Options o;
    auto& cli = runner.cli();
    shatter::demo::addBallOptions(cli, o.ball, "(both balls)");
    cli.add_option("--tets", o.tets, "TetGen mesh (PATH.ele with PATH.node) to use for both walls");
    const CLI::Option* strength =
        cli.add_option("--strength", o.strength, "link strength per m^2 of shared face in Pa (default: adobe's)");
    cli.add_option("--noise-amplitude", o.amplitude, "strength × (1 + amplitude · noise) on the noisy wall");
    cli.add_option("--noise-scale", o.scale, "size of the noise features in m");
    return runner.run(argc, argv, [&](shatter::demo::Scene& scene) {
        shatter::demo::checkBall(o.ball);
        o.strengthGiven = strength->count() > 0;
        shatter::demo::useSplitImpulsesOnly(scene.world());
        scene.addGround();
        const shatter::lattice::TetMesh mesh = wallMesh(o);
        for (const auto& w : mesh.warnings) std::cerr << "shatter-noise: warning: " << w << "\n";
        double width = 0;
        {
            double lo = INFINITY, hi = -INFINITY;
            for (const auto& n : mesh.nodes) lo = std::min(lo, n.x()), hi = std::max(hi, n.x());
            width = hi - lo;
        }
        const Wall uniform = addWall(scene, mesh, o, false, -0.75 * width);
        const Wall noisy = addWall(scene, mesh, o, true, 0.75 * width);
        scene.onFrame([&scene, uniform, noisy](const shatter::demo::Frame& frame) {
            if (frame.index != frame.count) return;
            const auto a = shatter::demo::latticeCounts(*uniform.body), b = shatter::demo::latticeCounts(*noisy.body);
            for (const char* key : {"tets", "links", "links_broken", "fragments"})
                scene.addSummary(key, a[key].get<int>() + b[key].get<int>());
            for (const char* key : {"mass_initial", "mass_final"})
                scene.addSummary(key, a[key].get<double>() + b[key].get<double>());
            const double before = a["mass_initial"].get<double>() + b["mass_initial"].get<double>();
            const double after = a["mass_final"].get<double>() + b["mass_final"].get<double>();
            scene.addSummary("mass_relative_change", (after - before) / before);
            scene.addSummary(uniform.key, a);
            scene.addSummary(noisy.key, b);
        });
    });
}
