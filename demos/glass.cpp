// shatter-glass: a pane of glass hangs in a frame on two hinge joint boxes and a ball hits it
// off-centre. A glass pattern (radial sectors times rings) is placed at the hit: a hole and
// radial shards break free, and the rest of the pane stays on its hinges, which are handed on
// to the piece that holds them (source 000 §3.6, last paragraph).
#include "demos/FractureScenes.h"
#include "demos/MeshOptions.h"
#include "demos/runner/DemoRunner.h"

int main(int argc, char** argv) {
    shatter::demo::DemoRunner runner("glass",
                                     "A pane of glass on two hinges, hit off-centre by a ball, shatters around the hit.");
    shatter::demo::GlassScene glass;
    shatter::demo::addBallOptions(runner.cli(), glass.ball);
    runner.cli().add_option("--mesh", glass.mesh, "OBJ file to hang in place of the pane (its first body is hit)");
    shatter::demo::addMeshOptions(runner.cli(), glass.meshSettings);
    shatter::demo::addFractureOptions(runner.cli(), glass.pane.fracture);
    std::unique_ptr<shatter::demo::FractureSummary> summary;
    return runner.run(argc, argv, [&](shatter::demo::Scene& scene) {
        summary = std::make_unique<shatter::demo::FractureSummary>(scene);
        shatter::demo::buildGlassScene(scene, glass, *summary);
        scene.onFrame([&summary](const shatter::demo::Frame& f) { summary->frame(f); });
    });
}
