#pragma once
// The program around every demo: command line, world, stepping, progress, output files,
// error reporting. A demo's main only adds its own options and builds its scene:
//
//   int main(int argc, char** argv) {
//       shatter::demo::DemoRunner runner("drop", "Meshes dropped on the ground, coming to rest.");
//       std::string mesh;
//       runner.cli().add_option("--mesh", mesh, "OBJ file to drop instead of the built-in set");
//       return runner.run(argc, argv, [&](shatter::demo::Scene& scene) {
//           scene.addGround();
//           ...
//       });
//   }
#include "demos/runner/RunOptions.h"
#include "demos/runner/Scene.h"

#include <CLI/CLI.hpp>

#include <functional>
#include <iostream>
#include <string>
#include <vector>

namespace shatter::demo {

class DemoRunner {
public:
    using Setup = std::function<void(Scene&)>;

    // `name` makes the program name shatter-<name> and the default output directory out/<name>.
    DemoRunner(std::string name, std::string description);

    // Add demo-specific options here before run().
    CLI::App& cli() { return app_; }
    const RunOptions& options() const { return options_; }
    const std::string& program() const { return program_; }

    // Parses the command line, builds the scene with `setup`, steps it and writes the
    // output. Returns the exit code: 0, CLI11's code for a command-line error (0 for
    // --help), 1 for any other error. Never throws: errors are printed to the error stream
    // as "shatter-<name>: error: <message>".
    int run(int argc, const char* const* argv, const Setup& setup);
    // Same with the arguments after the program name, for tests.
    int run(std::vector<std::string> args, const Setup& setup);

    // Where the report and the errors go (std::cout and std::cerr by default). The progress
    // line is only drawn on std::cerr, and only when it is a terminal.
    void setStreams(std::ostream& out, std::ostream& err);

private:
    int simulate(const Setup& setup);

    std::string name_, description_, program_;
    CLI::App app_;
    RunOptions options_;
    std::ostream* out_ = &std::cout;
    std::ostream* err_ = &std::cerr;
};

} // namespace shatter::demo
