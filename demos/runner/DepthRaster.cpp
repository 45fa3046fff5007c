#include "demos/runner/DepthRaster.h"

#include <algorithm>
#include <cmath>

namespace shatter::demo {

std::uint32_t packRgb(double r, double g, double b) {
    // Rounds by adding a half (std::lround is a library call, and this runs per floor sample).
    auto channel = [](double c) { return std::uint32_t(std::clamp(c, 0.0, 1.0) * 255.0 + 0.5); };
    return channel(r) << 16 | channel(g) << 8 | channel(b);
}

DepthRaster::DepthRaster(int width, int height, int samples, std::uint32_t background)
    : width_(width), height_(height), samples_(samples), sw_(width * samples), sh_(height * samples),
      colour_(size_t(sw_) * size_t(sh_), background), inverseDepth_(colour_.size(), 0.0f),
      face_(colour_.size(), kNoFace) {}

Eigen::Vector2d DepthRaster::centre(size_t sample) const {
    const double x = double(sample % size_t(sw_)) + 0.5, y = double(sample / size_t(sw_)) + 0.5;
    return {x / samples_, y / samples_};
}

// Visits the samples whose centres lie inside the triangle (either winding), with the
// barycentric weights of the centre.
template <class Visit>
void DepthRaster::scan(const std::array<Eigen::Vector2d, 3>& pixels, Visit&& visit) const {
    std::array<Eigen::Vector2d, 3> p;
    for (int k = 0; k < 3; ++k) p[size_t(k)] = pixels[size_t(k)] * samples_;
    const double area = (p[1] - p[0]).x() * (p[2] - p[0]).y() - (p[1] - p[0]).y() * (p[2] - p[0]).x();
    if (!(std::abs(area) > 1e-12)) return; // also rejects NaN
    const double xlo = std::min({p[0].x(), p[1].x(), p[2].x()}), xhi = std::max({p[0].x(), p[1].x(), p[2].x()});
    const double ylo = std::min({p[0].y(), p[1].y(), p[2].y()}), yhi = std::max({p[0].y(), p[1].y(), p[2].y()});
    const int x0 = std::max(0, int(std::floor(xlo))), x1 = std::min(sw_ - 1, int(std::ceil(xhi)));
    const int y0 = std::max(0, int(std::floor(ylo))), y1 = std::min(sh_ - 1, int(std::ceil(yhi)));
    const double inv = 1.0 / area;
    auto edge = [](const Eigen::Vector2d& a, const Eigen::Vector2d& b, double x, double y) {
        return (b.x() - a.x()) * (y - a.y()) - (b.y() - a.y()) * (x - a.x());
    };
    for (int y = y0; y <= y1; ++y)
        for (int x = x0; x <= x1; ++x) {
            const double cx = x + 0.5, cy = y + 0.5;
            const double w0 = edge(p[1], p[2], cx, cy) * inv, w1 = edge(p[2], p[0], cx, cy) * inv;
            const double w2 = 1.0 - w0 - w1;
            if (w0 < 0 || w1 < 0 || w2 < 0) continue;
            visit(size_t(y) * size_t(sw_) + size_t(x), w0, w1, w2);
        }
}

void DepthRaster::triangle(const std::array<Eigen::Vector2d, 3>& pixels, const std::array<double, 3>& inverseDepth,
                           std::uint32_t colour, int face) {
    scan(pixels, [&](size_t s, double w0, double w1, double w2) {
        const float z = float(w0 * inverseDepth[0] + w1 * inverseDepth[1] + w2 * inverseDepth[2]);
        if (z <= inverseDepth_[s]) return;
        inverseDepth_[s] = z;
        colour_[s] = colour;
        face_[s] = face;
    });
}

void DepthRaster::cover(const std::array<Eigen::Vector2d, 3>& pixels, const std::function<void(size_t)>& visit) const {
    scan(pixels, [&](size_t s, double, double, double) { visit(s); });
}

std::vector<std::uint32_t> DepthRaster::pixels() const {
    std::vector<std::uint32_t> out(size_t(width_) * size_t(height_));
    const int n = samples_ * samples_;
    for (int y = 0; y < height_; ++y)
        for (int x = 0; x < width_; ++x) {
            unsigned r = 0, g = 0, b = 0;
            for (int j = 0; j < samples_; ++j)
                for (int i = 0; i < samples_; ++i) {
                    const std::uint32_t c = colour_[size_t(y * samples_ + j) * size_t(sw_) + size_t(x * samples_ + i)];
                    r += c >> 16 & 255;
                    g += c >> 8 & 255;
                    b += c & 255;
                }
            out[size_t(y) * size_t(width_) + size_t(x)] = (r + n / 2) / n << 16 | (g + n / 2) / n << 8 | (b + n / 2) / n;
        }
    return out;
}

} // namespace shatter::demo
