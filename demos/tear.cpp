// shatter-tear: a curtain of 50 × 50 quads hangs by ball-joint boxes from a static rail and a
// ball is thrown into it (source 000 §3.6). The curtain is a soft body: it stretches where the
// ball pushes it, and where vertices that share a global id drift more than the tear distance
// apart, the connection between their primitives breaks. By default only the connections
// across the tear line the artist drew (a `tear.curtain` polyline down the middle) may break;
// with --everywhere every connection may. The flood fill over shared global ids opens the
// visual mesh along the broken connections, and the parts become soft bodies of their own
// (curtain.1, curtain.2), each keeping the joints whose boxes it touches. A wall behind stops
// the ball.
#include "demos/MeshOptions.h"
#include "demos/TearCurtain.h"
#include "demos/TearSummary.h"
#include "demos/runner/DemoRunner.h"

int main(int argc, char** argv) {
    shatter::demo::DemoRunner runner("tear", "A curtain hanging from a rail is hit by a ball and tears along its tear line.");
    shatter::demo::TearCurtain curtain;
    shatter::demo::addBallOptions(runner.cli(), curtain.ball);
    runner.cli().add_option("--mesh", curtain.mesh, "OBJ file to hang instead of the curtain (its bodies, joint boxes and tear lines)");
    runner.cli().add_option("--static", curtain.staticName, "the body of --mesh that is static (the rail)")->capture_default_str();
    runner.cli().add_option("--quads", curtain.quads, "the built-in curtain's quads per side")->capture_default_str()->check(CLI::Range(2, 400));
    shatter::demo::addMeshOptions(runner.cli(), curtain.meshSettings);
    // 4 mm along the tear line; with --everywhere 15 mm, since at 4 mm the cloth's own weight
    // tears the rows under the joint boxes, where held particles meet free ones.
    double distance = 0.0;
    runner.cli().add_option("--tear-distance", distance,
                            "drift of shared vertices that breaks a connection, m (default 0.004, with --everywhere 0.015)");
    runner.cli().add_flag("--everywhere", curtain.cloth.tear.everywhere, "every connection may break, not only the tear lines'");
    runner.cli().add_option("--stiffness", curtain.cloth.solver.stiffness, "shape-matching stiffness of the cloth in [0, 1]")
        ->capture_default_str();
    std::unique_ptr<shatter::demo::TearSummary> summary;
    return runner.run(argc, argv, [&](shatter::demo::Scene& scene) {
        curtain.cloth.tear.distance = runner.cli().count("--tear-distance") ? distance : curtain.cloth.tear.everywhere ? 0.015 : 0.004;
        const auto cloths = shatter::demo::buildTearCurtain(scene, curtain, "shatter-tear");
        summary = std::make_unique<shatter::demo::TearSummary>(scene);
        for (shatter::VisualBody* body : cloths) summary->watch(*body);
        scene.onFrame([&summary](const shatter::demo::Frame& f) { summary->frame(f); });
    });
}
