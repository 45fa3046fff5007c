// The MPM crack solver alone (shatter::mpm, no Bullet), against the installed package: a scene
// from in-memory JSON, a few frames, and a check that the disc fell and landed.
#include <shatter/plugin/mpm/SceneFile.h>
#include <shatter/plugin/mpm/Solver2D.h>

#include <algorithm>
#include <cstdio>

int main() {
    // A jello disc (radius 0.2 m, 5 cm cells) dropped 0.1 m onto the ground half-plane y = 0.
    const char* json = R"({
        "grid": {"dx": 0.05},
        "time": {"end": 0.5, "frame": 0.05},
        "materials": {"jello": {"model": "corotated", "E": 2e4, "nu": 0.3, "rho": 1000}},
        "bodies": [{"shape": {"type": "circle", "center": [0, 0.3], "radius": 0.2}, "material": "jello"}],
        "colliders": [{"type": "half_plane", "point": [0, 0], "normal": [0, 1]}]
    })";
    shatter::mpm::Scene scene = shatter::mpm::parseScene(json, "consumer.json");
    shatter::mpm::Solver2D solver(scene);
    while (solver.time() < scene.time.end - 1e-9) solver.advance(scene.time.frame);
    double lowest = 1e9;
    for (const auto& x : solver.particles().x) lowest = std::min(lowest, x.y());
    std::printf("mpm: %zu particles, %ld substeps, t = %.3f s, lowest particle y = %.4f m\n", solver.particles().size(),
                solver.substeps(), solver.time(), lowest);
    // Fell 0.1 m onto the ground (the lowest particle starts at 0.1 + spacing/2) and did not
    // go through it (deeper than a cell).
    return lowest < 0.1 && lowest > -scene.grid.dx ? 0 : 1;
}
