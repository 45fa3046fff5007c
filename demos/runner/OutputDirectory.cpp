#include "demos/runner/OutputDirectory.h"

#include <algorithm>
#include <stdexcept>
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
    for (const auto& entry : fs::directory_iterator(out.path))
        if (entry.is_regular_file() && isFrameFile(entry.path()) && fs::remove(entry.path(), ec)) ++out.staleFramesRemoved;
    return out;
}

} // namespace shatter::demo
