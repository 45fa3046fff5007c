#include "demos/runner/RunOptions.h"

#include <charconv>
#include <cmath>
#include <limits>
#include <sstream>
#include <string_view>

namespace shatter::demo {

namespace {

// CLI11's own conversion goes through strtoll with base 0, which reads "010" as 8 and
// "-1" as a huge unsigned value; these parse the whole string as decimal or fail.
template <class T>
bool parseWhole(std::string_view text, T& value) {
    const char* end = text.data() + text.size();
    const auto result = std::from_chars(text.data(), end, value);
    return result.ec == std::errc() && result.ptr == end;
}

CLI::ValidationError invalid(const std::string& option, const std::string& text, const std::string& expected) {
    return CLI::ValidationError(option, "expected " + expected + ", got '" + text + "'");
}

int integerAtLeast(const std::string& option, const std::string& text, int minimum) {
    long long value = 0;
    if (!parseWhole(text, value) || value < minimum || value > std::numeric_limits<int>::max())
        throw invalid(option, text, "an integer >= " + std::to_string(minimum));
    return int(value);
}

double positiveNumber(const std::string& option, const std::string& text) {
    double value = 0;
    if (!parseWhole(text, value) || !std::isfinite(value) || value <= 0) throw invalid(option, text, "a number > 0");
    return value;
}

// "WIDTHxHEIGHT", each side 16 to 8192 pixels.
void imageSize(const std::string& option, const std::string& text, int& width, int& height) {
    const auto x = text.find_first_of("xX");
    int w = 0, h = 0;
    const bool ok = x != std::string::npos && parseWhole(std::string_view(text).substr(0, x), w) &&
                    parseWhole(std::string_view(text).substr(x + 1), h) && w >= 16 && h >= 16 && w <= 8192 &&
                    h <= 8192;
    if (!ok) throw invalid(option, text, "WIDTHxHEIGHT with sides from 16 to 8192 pixels, e.g. 1280x720");
    width = w;
    height = h;
}

std::string numberText(double value) {
    std::ostringstream s;
    s << value;
    return s.str();
}

} // namespace

void addRunOptions(CLI::App& app, RunOptions& o) {
    app.add_option_function<std::string>(
           "--frames", [&o](const std::string& s) { o.frames = integerAtLeast("--frames", s, 1); },
           "Frames to simulate and write (>= 1)")
        ->type_name("N")
        ->default_str(std::to_string(o.frames));
    app.add_option_function<std::string>(
           "--fps", [&o](const std::string& s) { o.fps = positiveNumber("--fps", s); },
           "Frames per simulated second (> 0)")
        ->type_name("F")
        ->default_str(numberText(o.fps));
    app.add_option_function<std::string>(
           "--substeps", [&o](const std::string& s) { o.substeps = integerAtLeast("--substeps", s, 1); },
           "Fixed physics steps per frame (>= 1): stepSimulation(1/fps, K, 1/(fps*K))")
        ->type_name("K")
        ->default_str(std::to_string(o.substeps));
    app.add_option("--out", o.out, "Output directory, created with its parents")->type_name("DIR")->capture_default_str();
    app.add_option_function<std::string>(
           "--seed",
           [&o](const std::string& s) {
               if (!parseWhole(s, o.seed)) throw invalid("--seed", s, "an unsigned 64-bit integer");
           },
           "Seed of the scene's random choices; the same seed gives the same frames")
        ->type_name("S")
        ->default_str(std::to_string(o.seed));
    app.add_flag("--quiet,-q", o.quiet, "No progress line and no final report");
    app.add_option_function<std::string>(
           "--png-every", [&o](const std::string& s) { o.pngEvery = integerAtLeast("--png-every", s, 0); },
           "Also write frame_NNNN.png every N frames (0: only final.png)")
        ->type_name("N")
        ->default_str(std::to_string(o.pngEvery));
    app.add_option_function<std::string>(
           "--png-size", [&o](const std::string& s) { imageSize("--png-size", s, o.pngWidth, o.pngHeight); },
           "Size of the pictures in pixels")
        ->type_name("WxH")
        ->default_str(std::to_string(o.pngWidth) + "x" + std::to_string(o.pngHeight));
    app.add_flag_callback("--no-gltf", [&o] { o.gltf = false; }, "Do not write scene.glb (the whole run as one animated glTF file)");
}

} // namespace shatter::demo
