// shatter-wall: the source's Fig. 2 (002 §4). An adobe wall of about 4,000 tets, anchored to
// the ground, is struck by a heavy ball; the lattice breaks where its link forces say and the
// pieces fly on as rigid bodies.
#include "demos/LatticeScenes.h"
#include "demos/bench/ContactOptions.h"
#include "demos/runner/DemoRunner.h"

int main(int argc, char** argv) {
    shatter::demo::DemoRunner runner("wall", "An adobe wall anchored to the ground, struck by a heavy ball (source 002 Fig. 2).");
    shatter::demo::WallOptions o;
    shatter::demo::addOptions(runner.cli(), o);
    shatter::bench::addContactOptions(runner.cli());
    return runner.run(argc, argv, [&](shatter::demo::Scene& scene) { shatter::demo::buildScene(scene, o, "shatter-wall"); });
}
