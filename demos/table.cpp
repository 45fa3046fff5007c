// shatter-table: the source's Fig. 3 (002 §4). A glass table top on four legs, with a cleaving
// plane through its middle that weakens the links there, and a ball dropped on it.
#include <shatter/bullet_ext/lattice/LatticeBody.h>
#include <shatter/bullet_ext/lattice/LatticeSystem.h>
#include "demos/LatticeDemo.h"
#include "demos/runner/DemoRunner.h"
#include <shatter/plugin/common/InputError.h>
#include <shatter/plugin/lattice/TetGenReader.h>
#include <shatter/plugin/lattice/TetGenerators.h>

#include <BulletCollision/CollisionShapes/btBoxShape.h>
#include <BulletCollision/CollisionShapes/btSphereShape.h>

#include <cmath>
#include <iostream>

namespace {

struct Options {
    shatter::demo::Ball ball{6.0, 8.0, 0.1}; // downward, from 0.4 m above the top
    double cleaving = 0.3;   // strength factor on the plane (1 = no plane)
    double jitter = 0.1;
    std::string tets;
    double strength = 0.0;   // Pa, when given: instead of the material's
    std::string material = "glass";
    bool spreading = true;
    bool replay = true;
    bool freeze = true;
};

constexpr double kLegHeight = 0.72;

// A 1.2 × 0.7 m top, 2 cm thick, in 4 cm cells: 3,150 tets.
shatter::lattice::TetMesh topMesh(const Options& o, std::uint64_t seed) {
    if (!o.tets.empty()) return shatter::lattice::readTetGen(o.tets);
    shatter::lattice::GeneratorOptions g;
    g.name = "top";
    g.jitter = o.jitter;
    g.seed = seed;
    return shatter::lattice::tetSlab(1.2, 0.7, 0.02, 0.04, 1, g);
}

} // namespace

int main(int argc, char** argv) {
    shatter::demo::DemoRunner runner("table", "A glass table top with a cleaving plane, a ball dropped on it (source 002 Fig. 3).");
    Options o;
    auto& cli = runner.cli();
    shatter::demo::addBallOptions(cli, o.ball, "(dropped from 0.4 m above the top)");
    cli.add_option("--tets", o.tets, "TetGen mesh (PATH.ele with PATH.node) to use as the table top (mesh units m, y up)");
    cli.add_option("--cleaving", o.cleaving, "strength factor of the links on the plane x = 0 (1 = no cleaving plane)");
    cli.add_option("--jitter", o.jitter, "node jitter of the built-in top, fraction of a cell in [0, 0.2]");
    const CLI::Option* strength =
        cli.add_option("--strength", o.strength, "link strength per m^2 of shared face in Pa (default: the material's)");
    cli.add_option("--material", o.material, "glass, ceramic, adobe, brick or concrete");
    cli.add_flag("!--no-spreading", o.spreading, "turn off dynamic weakening around breaks");
    cli.add_flag("!--no-replay", o.replay, "keep the impulses of a breaking body's contacts instead of solving them again "
                                           "against the fragments");
    cli.add_flag("!--no-freeze", o.freeze, "let resting fragments only sleep (Bullet's islands) instead of freezing them");
    return runner.run(argc, argv, [&](shatter::demo::Scene& scene) {
        shatter::demo::checkBall(o.ball);
        if (!(std::isfinite(o.cleaving) && o.cleaving > 0)) throw shatter::InputError("--cleaving must be finite and > 0");
        shatter::demo::useSplitImpulsesOnly(scene.world());
        scene.addGround();
        const shatter::lattice::TetMesh mesh = topMesh(o, scene.seed());
        for (const auto& w : mesh.warnings) std::cerr << "shatter-table: warning: " << w << "\n";
        Eigen::Vector3d lo = Eigen::Vector3d::Constant(INFINITY), hi = -lo;
        for (const auto& n : mesh.nodes) lo = lo.cwiseMin(n), hi = hi.cwiseMax(n);
        const Eigen::Vector3d centre = 0.5 * (lo + hi);
        // Four legs under the corners, the top resting on them.
        const double leg = 0.03;
        for (int sx : {-1, 1})
            for (int sz : {-1, 1}) {
                const btVector3 at(btScalar(centre.x() + sx * (0.5 * (hi.x() - lo.x()) - 2 * leg)), btScalar(0.5 * kLegHeight),
                                   btScalar(centre.z() + sz * (0.5 * (hi.z() - lo.z()) - 2 * leg)));
                scene.addRigidBody(std::make_unique<btBoxShape>(btVector3(btScalar(leg), btScalar(0.5 * kLegHeight), btScalar(leg))),
                                   0.0, btTransform(btQuaternion::getIdentity(), at), "leg");
            }
        shatter::LatticeSettings settings;
        settings.name = "top";
        settings.material = shatter::lattice::materialNamed(o.material);
        if (strength->count()) settings.material.strength = o.strength; // the body reports a bad one
        settings.seed = scene.seed();
        settings.analysis.spreading.enabled = o.spreading;
        settings.replayImpacts = o.replay;
        settings.rest.freezeAtRest = o.freeze;
        if (o.cleaving != 1.0) {
            shatter::lattice::CleavingPlane plane;
            plane.point = centre;
            plane.normal = Eigen::Vector3d::UnitX();
            plane.distance = 0.25 * (hi.y() - lo.y()); // faces lying across the thickness at x = 0
            plane.factor = o.cleaving;
            settings.cleavingPlanes.push_back(plane);
        }
        const btTransform pose(btQuaternion::getIdentity(), btVector3(0, btScalar(kLegHeight - lo.y() + 0.001), 0));
        shatter::LatticeBody& top = scene.plugin().addLatticeBody(mesh, settings, pose);
        // The ball falls on the top a little off the plane, so the crack has to find it.
        const btVector3 ballAt(btScalar(centre.x() + 0.06), btScalar(kLegHeight + (hi.y() - lo.y()) + 0.4),
                               btScalar(centre.z() + 0.05));
        shatter::demo::launchBall(scene, o.ball, ballAt, btVector3(0, -1, 0));
        scene.onFrame([&scene, &top](const shatter::demo::Frame& frame) {
            if (frame.index != frame.count) return;
            shatter::demo::addSummaries(scene, shatter::demo::latticeCounts(top));
            int onPlane = 0;
            for (const auto& l : top.lattice().links()) {
                if (!l.broken) continue;
                for (const auto& p : top.settings().cleavingPlanes) onPlane += shatter::lattice::faceNearPlane(top.lattice(), l, p);
            }
            scene.addSummary("links_broken_on_cleaving_plane", onPlane);
        });
    });
}
