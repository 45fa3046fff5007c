// shatter-wall: the source's Fig. 2 (002 §4). An adobe wall of about 4,000 tets, anchored to
// the ground, is struck by a heavy ball; the lattice breaks where its link forces say and the
// pieces fly on as rigid bodies.
#include <shatter/bullet_ext/Convert.h>
#include <shatter/bullet_ext/lattice/LatticeBody.h>
#include <shatter/bullet_ext/lattice/LatticeSystem.h>
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
    shatter::demo::Ball ball{9.0, 400.0, 0.25};
    double jitter = 0.15;     // of a cell
    std::string tets;         // .ele/.node to use instead of the built-in wall
    std::string material = "adobe";
    double strength = 0.0;    // Pa, when given: instead of the material's
    double density = 0.0;     // kg/m³, when given: instead of the material's
    bool spreading = true;
    bool replay = true;
    bool freeze = true;
};

// The built-in wall: 17 × 10 × 4 cells of 10 cm, six tets each: 4,080 tets, as in the source.
shatter::lattice::TetMesh wallMesh(const Options& o, std::uint64_t seed) {
    if (!o.tets.empty()) return shatter::lattice::readTetGen(o.tets);
    shatter::lattice::GeneratorOptions g;
    g.name = "wall";
    g.jitter = o.jitter;
    g.seed = seed;
    return shatter::lattice::tetBox({1.7, 1.0, 0.4}, {17, 10, 4}, g);
}

// Stands a mesh on the ground: returns the pose lifting its lowest node to y = 0 and the
// tets with a face on that plane (anchored).
btTransform standOnGround(const shatter::lattice::TetMesh& mesh, std::vector<int>& anchored) {
    double lowest = INFINITY;
    for (const auto& n : mesh.nodes) lowest = std::min(lowest, n.y());
    anchored = shatter::lattice::tetsWithFaceOnPlane(mesh, {0, 1, 0}, lowest, 1e-6);
    return btTransform(btQuaternion::getIdentity(), btVector3(0, btScalar(-lowest), 0));
}

} // namespace

int main(int argc, char** argv) {
    shatter::demo::DemoRunner runner("wall", "An adobe wall anchored to the ground, struck by a heavy ball (source 002 Fig. 2).");
    Options o;
    auto& cli = runner.cli();
    shatter::demo::addBallOptions(cli, o.ball);
    cli.add_option("--tets", o.tets, "TetGen mesh (PATH.ele with PATH.node) to use instead of the built-in wall");
    cli.add_option("--jitter", o.jitter, "node jitter of the built-in wall, fraction of a cell in [0, 0.2]");
    const CLI::Option* strength =
        cli.add_option("--strength", o.strength, "link strength per m^2 of shared face in Pa (default: the material's)");
    const CLI::Option* density = cli.add_option("--density", o.density, "density in kg/m^3 (default: the material's)");
    cli.add_option("--material", o.material, "adobe, brick, concrete, glass or ceramic");
    cli.add_flag("!--no-spreading", o.spreading, "turn off dynamic weakening around breaks");
    cli.add_flag("!--no-replay", o.replay, "keep the impulses of a breaking body's contacts instead of solving them again "
                                           "against the fragments");
    cli.add_flag("!--no-freeze", o.freeze, "let resting fragments only sleep (Bullet's islands) instead of freezing them");
    return runner.run(argc, argv, [&](shatter::demo::Scene& scene) {
        shatter::demo::checkBall(o.ball);
        shatter::demo::useSplitImpulsesOnly(scene.world());
        scene.addGround();
        shatter::lattice::TetMesh mesh = wallMesh(o, scene.seed());
        for (const auto& w : mesh.warnings) std::cerr << "shatter-wall: warning: " << w << "\n";
        shatter::LatticeSettings settings;
        settings.name = "wall";
        settings.material = shatter::lattice::materialNamed(o.material);
        // Bad values (zero, negative, not finite) are reported by the body, naming it.
        if (strength->count()) settings.material.strength = o.strength;
        if (density->count()) settings.material.density = o.density;
        settings.seed = scene.seed();
        settings.analysis.spreading.enabled = o.spreading;
        settings.replayImpacts = o.replay;
        settings.rest.freezeAtRest = o.freeze;
        const btTransform pose = standOnGround(mesh, settings.fixedTets);
        if (settings.fixedTets.empty()) throw shatter::InputError("the wall mesh has no face on its lowest plane to anchor it by");
        shatter::LatticeBody& wall = scene.plugin().addLatticeBody(mesh, settings, pose);
        // The ball flies at the wall's face, a little below the middle of its height.
        double top = -INFINITY, front = -INFINITY;
        for (const auto& n : mesh.nodes) top = std::max(top, n.y()), front = std::max(front, n.z());
        const double height = top + double(pose.getOrigin().y());
        const btVector3 ballAt(0, btScalar(0.45 * height), btScalar(front + o.ball.radius + 0.3));
        shatter::demo::launchBall(scene, o.ball, ballAt, btVector3(0, 0, -1)).setFriction(0.5);
        scene.onFrame([&scene, &wall](const shatter::demo::Frame& frame) {
            if (frame.index == frame.count) shatter::demo::addSummaries(scene, shatter::demo::latticeCounts(wall));
        });
    });
}
