#pragma once
// The command-line options every demo shares.
#include <CLI/CLI.hpp>

#include <cstdint>
#include <string>

namespace shatter::demo {

struct RunOptions {
    int frames = 240;      // frames to simulate and write
    double fps = 60;       // frames per simulated second
    int substeps = 4;      // fixed internal steps per frame
    std::string out;       // output directory (the runner sets out/<demo name>)
    std::uint64_t seed = 1;
    bool quiet = false;    // no progress line, no final report
    int pngEvery = 0;      // also write frame_NNNN.png every this many frames; 0 = only final.png
    int pngWidth = 1280;
    int pngHeight = 720;
    bool gltf = true;      // write scene.glb (the whole run, animated)

    double substepSeconds() const { return 1.0 / (fps * substeps); }
};

// Adds --frames, --fps, --substeps, --out, --seed, --quiet, --png-every, --png-size and --no-gltf to
// `app`, bound to `options`. Values are parsed strictly (decimal, whole string, finite,
// in range); a bad one is a CLI::ValidationError whose message names the option.
void addRunOptions(CLI::App& app, RunOptions& options);

} // namespace shatter::demo
