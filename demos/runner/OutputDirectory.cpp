#include "demos/runner/OutputDirectory.h"

#include <algorithm>
#include <cstdio>
#include <stdexcept>
#include <cerrno>
#include <system_error>

namespace shatter::demo {

namespace {

// frame_<digits>.obj or frame_<digits>.png: the names FrameWriter and the renderer use.
bool isFrameFile(const std::filesystem::path& file) {
    const std::string extension = file.extension().string();
    if (extension != ".obj" && extension != ".png") return false;
    const std::string stem = file.stem().string();
    if (stem.rfind("frame_", 0) != 0 || stem.size() == 6) return false;
    return std::all_of(stem.begin() + 6, stem.end(), [](char c) { return c >= '0' && c <= '9'; });
}

} // namespace

OutputDirectory prepareOutputDirectory(const std::string& dir) {
    namespace fs = std::filesystem;
    if (dir.empty()) throw std::runtime_error("--out: the output directory name is empty");
    OutputDirectory out;
    out.path = fs::absolute(fs::path(dir)).lexically_normal();
    if (!out.path.has_filename()) out.path = out.path.parent_path(); // "out/drop/" -> "out/drop"
    std::error_code ec;
    fs::create_directories(out.path, ec);
    if (ec || !fs::is_directory(out.path))
        throw std::runtime_error("--out " + dir + ": cannot create the directory" + (ec ? ": " + ec.message() : ""));
    // Being a directory is not enough: a read-only one would fail only after the whole run.
    const fs::path probe = out.path / ".shatter-write-check";
    if (std::FILE* f = std::fopen(probe.c_str(), "wb")) {
        std::fclose(f);
        fs::remove(probe, ec);
    } else {
        throw std::runtime_error("--out " + dir + ": cannot write in the directory: " + std::generic_category().message(errno));
    }
    for (const auto& entry : fs::directory_iterator(out.path))
        if (entry.is_regular_file() && isFrameFile(entry.path()) && fs::remove(entry.path(), ec)) ++out.staleFramesRemoved;
    // Written at the end of a run: an earlier run's must not pass for this one's (--no-gltf, a failed run).
    for (const char* file : {"scene.glb", "story.png"}) fs::remove(out.path / file, ec);
    return out;
}

} // namespace shatter::demo
