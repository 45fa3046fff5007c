#pragma once
// A cairo image the pictures are put together on: rendered scenes pasted in, text lines on
// top, written as a PNG.
#include "demos/runner/PngRenderer.h"

#include <filesystem>
#include <memory>
#include <string>

typedef struct _cairo_surface cairo_surface_t;
typedef struct _cairo cairo_t;

namespace shatter::demo {

class PngCanvas {
public:
    // Filled with the scene's background colour.
    PngCanvas(int width, int height);
    ~PngCanvas();
    PngCanvas(const PngCanvas&) = delete;
    PngCanvas& operator=(const PngCanvas&) = delete;

    // Copies the scene's pixels with their top-left corner at (x, y).
    void paste(const SceneImage& scene, int x, int y);
    // `bold` then `normal` on one baseline starting at (x, y), as the title of a picture.
    void titleLine(double x, double y, const std::string& bold, const std::string& normal, double size = 22);
    // A frame around the rectangle, `width` pixels wide, in the accent colour (the story's
    // marked moment).
    void accentFrame(double x, double y, double w, double h, double width);
    // Text in the accent colour.
    void accentText(double x, double y, const std::string& text, double size);

    // Throws std::runtime_error naming the file when cairo cannot write it.
    void write(const std::filesystem::path& path);

private:
    std::unique_ptr<cairo_surface_t, void (*)(cairo_surface_t*)> surface_;
    std::unique_ptr<cairo_t, void (*)(cairo_t*)> cr_;
};

} // namespace shatter::demo
