// shatter-table: the source's Fig. 3 (002 §4). A glass table top on four legs, with a cleaving
// plane through its middle that weakens the links there, and a ball dropped on it.
#include "demos/LatticeScenes.h"
#include "demos/bench/ContactOptions.h"
#include "demos/runner/DemoRunner.h"

int main(int argc, char** argv) {
    shatter::demo::DemoRunner runner("table", "A glass table top with a cleaving plane, a ball dropped on it (source 002 Fig. 3).");
    shatter::demo::TableOptions o;
    shatter::demo::addOptions(runner.cli(), o);
    shatter::bench::addContactOptions(runner.cli());
    return runner.run(argc, argv, [&](shatter::demo::Scene& scene) { shatter::demo::buildScene(scene, o, "shatter-table"); });
}
