// shatter-noise: the source's Fig. 4 (002 §4). Two identical walls side by side take the same
// impact: the left with uniform link strengths, the right with seeded 3D noise on its strengths
// and dynamic weakening around every break. The uniform wall cracks in the mesh's regular
// pattern; the noisy one breaks into irregular pieces.
#include "demos/LatticeScenes.h"
#include "demos/bench/ContactOptions.h"
#include "demos/runner/DemoRunner.h"

int main(int argc, char** argv) {
    shatter::demo::DemoRunner runner(
        "noise", "The same impact on a wall of uniform and of noisy, dynamically weakened strengths (source 002 Fig. 4).");
    shatter::demo::NoiseOptions o;
    shatter::demo::addOptions(runner.cli(), o);
    shatter::bench::addContactOptions(runner.cli());
    return runner.run(argc, argv, [&](shatter::demo::Scene& scene) { shatter::demo::buildScene(scene, o, "shatter-noise"); });
}
