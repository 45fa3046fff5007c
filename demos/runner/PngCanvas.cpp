#include "demos/runner/PngCanvas.h"

#include <cairo.h>

#include <cstring>
#include <stdexcept>

namespace shatter::demo {

namespace {

void setRgb(cairo_t* cr, double r, double g, double b) { cairo_set_source_rgb(cr, r, g, b); }
void textColour(cairo_t* cr) { setRgb(cr, 0.13, 0.15, 0.18); }
void accentColour(cairo_t* cr) { setRgb(cr, 0.80, 0.16, 0.10); }

} // namespace

PngCanvas::PngCanvas(int width, int height)
    : surface_(cairo_image_surface_create(CAIRO_FORMAT_RGB24, width, height), &cairo_surface_destroy),
      cr_(cairo_create(surface_.get()), &cairo_destroy) {
    setRgb(cr_.get(), 0.87, 0.89, 0.92);
    cairo_paint(cr_.get());
}

PngCanvas::~PngCanvas() = default;

void PngCanvas::paste(const SceneImage& scene, int x, int y) {
    cairo_surface_flush(surface_.get());
    unsigned char* data = cairo_image_surface_get_data(surface_.get());
    const int stride = cairo_image_surface_get_stride(surface_.get());
    const int width = cairo_image_surface_get_width(surface_.get()), height = cairo_image_surface_get_height(surface_.get());
    for (int row = 0; row < scene.height; ++row) {
        const int ty = y + row;
        if (ty < 0 || ty >= height) continue;
        auto* line = reinterpret_cast<std::uint32_t*>(data + size_t(ty) * size_t(stride));
        for (int col = 0; col < scene.width; ++col) {
            const int tx = x + col;
            if (tx >= 0 && tx < width) line[tx] = scene.pixels[size_t(row) * size_t(scene.width) + size_t(col)];
        }
    }
    cairo_surface_mark_dirty(surface_.get());
}

void PngCanvas::titleLine(double x, double y, const std::string& bold, const std::string& normal, double size) {
    cairo_t* cr = cr_.get();
    textColour(cr);
    cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_BOLD);
    cairo_set_font_size(cr, size);
    cairo_move_to(cr, x, y);
    cairo_show_text(cr, bold.c_str());
    cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
    cairo_set_font_size(cr, size * 15 / 22);
    double cx, cy;
    cairo_get_current_point(cr, &cx, &cy);
    cairo_move_to(cr, cx + (bold.empty() ? 0 : size * 0.7), y);
    cairo_show_text(cr, normal.c_str());
}

void PngCanvas::accentFrame(double x, double y, double w, double h, double width) {
    cairo_t* cr = cr_.get();
    accentColour(cr);
    cairo_set_line_width(cr, width);
    cairo_rectangle(cr, x + width / 2, y + width / 2, w - width, h - width);
    cairo_stroke(cr);
}

void PngCanvas::accentText(double x, double y, const std::string& text, double size) {
    cairo_t* cr = cr_.get();
    accentColour(cr);
    cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_BOLD);
    cairo_set_font_size(cr, size);
    cairo_move_to(cr, x, y);
    cairo_show_text(cr, text.c_str());
}

void PngCanvas::write(const std::filesystem::path& path) {
    cairo_surface_flush(surface_.get());
    const cairo_status_t status = cairo_surface_write_to_png(surface_.get(), path.c_str());
    if (status != CAIRO_STATUS_SUCCESS)
        throw std::runtime_error(path.string() + ": cannot write PNG: " + cairo_status_to_string(status));
}

} // namespace shatter::demo
