#pragma once
// The directory a run writes into.
#include <filesystem>
#include <string>

namespace shatter::demo {

struct OutputDirectory {
    std::filesystem::path path; // absolute
    int staleFramesRemoved = 0; // frame files of an earlier run, cleared so no old frame outlives a failed run
};

// Creates `dir` with its parents and removes every frame_NNNN.obj/.png an earlier run left
// there, so the directory only ever holds one run's sequence (a longer earlier run, or one
// that failed half way, cannot leave frames behind), and the scene.glb and story.png of an
// earlier run. Nothing else in it is touched. Throws std::runtime_error naming `dir` when it
// cannot be a directory or a file cannot be written in it.
OutputDirectory prepareOutputDirectory(const std::string& dir);

} // namespace shatter::demo
