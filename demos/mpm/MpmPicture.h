#pragma once
// A PNG of one frame of the 2D solver (cairo): particles coloured by their largest
// principal stress (blue: compression, white: zero, red: tension, symmetric scale from the
// frame's 99th percentile of |σ₁|), colliders in grey, the crack surfaces as dark lines,
// each active tip's J-integral contour in green and the tip itself in orange.
// The view is fixed at construction, so successive frames line up.
#include <shatter/plugin/mpm/Solver2D.h>

#include <filesystem>
#include <string>

namespace shatter::mpm::demo {

class MpmPicture {
public:
    // Frames the bodies as they are now, plus nearby colliders, in a width x height image.
    MpmPicture(const Solver2D& solver, int width, int height);

    // Writes the picture; `title` is printed above it. Throws std::runtime_error on failure.
    void write(const std::filesystem::path& path, const Solver2D& solver, const std::string& title) const;

private:
    int width_, height_;
    Vec2 centre_;
    double scale_; // pixels per metre
};

} // namespace shatter::mpm::demo
