// shatter-vase: a vase (a closed mesh of quads) and a bowl (an open surface of extruded faces)
// fall on a stone floor and shatter where they land (source 000 §2.3, §3.6): a fracture
// pattern is placed at the hardest contact, its cells cut the body's primitives, and the
// pieces fly on as rigid bodies; a piece hit hard enough again breaks once more.
#include "demos/FractureScenes.h"
#include "demos/MeshOptions.h"
#include "demos/runner/DemoRunner.h"

int main(int argc, char** argv) {
    shatter::demo::DemoRunner runner("vase", "A vase and a bowl dropped on a stone floor shatter where they land.");
    shatter::demo::VaseScene vase;
    runner.cli().add_option("--mesh", vase.mesh, "OBJ file to drop and break instead of the vase and the bowl");
    shatter::demo::addMeshOptions(runner.cli(), vase.meshSettings);
    shatter::demo::addFractureOptions(runner.cli(), vase.settings.fracture);
    runner.cli().add_option("--height", vase.height, "drop height of the lowest point, m")->capture_default_str();
    std::unique_ptr<shatter::demo::FractureSummary> summary;
    return runner.run(argc, argv, [&](shatter::demo::Scene& scene) {
        summary = std::make_unique<shatter::demo::FractureSummary>(scene);
        shatter::demo::buildVaseScene(scene, vase, *summary);
        scene.onFrame([&summary](const shatter::demo::Frame& f) { summary->frame(f); });
    });
}
