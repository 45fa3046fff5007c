#include "demos/mpm/MpmPicture.h"

#include <cairo.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <vector>

namespace shatter::mpm::demo {

namespace {

constexpr int kTitleBand = 40; // pixels at the top for the title line

struct Rgb {
    double r, g, b;
};

// Diverging blue-white-red for s in [-1, 1].
Rgb stressColour(double s) {
    s = std::clamp(s, -1.0, 1.0);
    const Rgb blue{0.15, 0.35, 0.85}, white{0.97, 0.97, 0.97}, red{0.85, 0.15, 0.12};
    const Rgb& end = s < 0 ? blue : red;
    const double t = std::abs(s);
    return {white.r + (end.r - white.r) * t, white.g + (end.g - white.g) * t, white.b + (end.b - white.b) * t};
}

double largestPrincipal(const Mat2& s) {
    const double mean = 0.5 * (s(0, 0) + s(1, 1));
    return mean + std::hypot(0.5 * (s(0, 0) - s(1, 1)), s(0, 1));
}

Box viewBox(const Solver2D& solver) {
    const Particles& P = solver.particles();
    Box b{P.x.front(), P.x.front()};
    for (const Vec2& x : P.x) {
        b.min = b.min.cwiseMin(x);
        b.max = b.max.cwiseMax(x);
    }
    // Colliders within one body size of the bodies are in view (a ground the body falls onto).
    const Vec2 size = (b.max - b.min).cwiseMax(Vec2::Constant(solver.scene().grid.dx));
    const Box near{b.min - size, b.max + size};
    Box out = b;
    auto include = [&](const Vec2& p) {
        const Vec2 q = p.cwiseMax(near.min).cwiseMin(near.max);
        out.min = out.min.cwiseMin(q);
        out.max = out.max.cwiseMax(q);
    };
    for (const auto& c : solver.scene().colliders) {
        if (auto h = dynamic_cast<const HalfPlaneCollider*>(c.get())) {
            // The line's closest point to the bodies' centre.
            const Vec2 mid = 0.5 * (b.min + b.max);
            include(mid - h->signedDistance(mid) * h->planeNormal());
        } else if (auto bx = dynamic_cast<const BoxCollider*>(c.get())) {
            include(bx->box().min);
            include(bx->box().max);
        } else if (auto ci = dynamic_cast<const CircleCollider*>(c.get())) {
            include(ci->center() - Vec2::Constant(ci->radius()));
            include(ci->center() + Vec2::Constant(ci->radius()));
        }
    }
    const Vec2 margin = 0.06 * (out.max - out.min).cwiseMax(Vec2::Constant(4 * solver.scene().grid.dx));
    return {out.min - margin, out.max + margin};
}

class Canvas {
public:
    Canvas(int width, int height, Vec2 centre, double scale)
        : surface_(cairo_image_surface_create(CAIRO_FORMAT_RGB24, width, height), cairo_surface_destroy),
          cr_(cairo_create(surface_.get()), cairo_destroy), width_(width), height_(height), centre_(centre),
          scale_(scale) {}

    cairo_t* cr() const { return cr_.get(); }
    Vec2 toPixels(const Vec2& p) const {
        return Vec2(0.5 * width_ + (p.x() - centre_.x()) * scale_,
                    kTitleBand + 0.5 * (height_ - kTitleBand) - (p.y() - centre_.y()) * scale_);
    }
    void colour(Rgb c, double a = 1) const { cairo_set_source_rgba(cr(), c.r, c.g, c.b, a); }
    void moveTo(const Vec2& p) const {
        const Vec2 q = toPixels(p);
        cairo_move_to(cr(), q.x(), q.y());
    }
    void lineTo(const Vec2& p) const {
        const Vec2 q = toPixels(p);
        cairo_line_to(cr(), q.x(), q.y());
    }
    void polyline(const std::vector<Vec2>& pts, bool closed) const {
        if (pts.empty()) return;
        moveTo(pts[0]);
        for (size_t k = 1; k < pts.size(); ++k) lineTo(pts[k]);
        if (closed) cairo_close_path(cr());
    }
    void save(const std::filesystem::path& path) const {
        cairo_surface_flush(surface_.get());
        if (cairo_surface_write_to_png(surface_.get(), path.string().c_str()) != CAIRO_STATUS_SUCCESS)
            throw std::runtime_error(path.string() + ": cannot write the PNG");
    }
    double scale() const { return scale_; }
    int width() const { return width_; }
    int height() const { return height_; }

private:
    std::unique_ptr<cairo_surface_t, void (*)(cairo_surface_t*)> surface_;
    std::unique_ptr<cairo_t, void (*)(cairo_t*)> cr_;
    int width_, height_;
    Vec2 centre_;
    double scale_;
};

void drawColliders(const Canvas& c, const Solver2D& solver) {
    c.colour({0.62, 0.64, 0.68});
    const double far = 1e4 * (c.width() + c.height()) / c.scale(); // "infinite" in metres
    for (const auto& col : solver.scene().colliders) {
        if (auto h = dynamic_cast<const HalfPlaneCollider*>(col.get())) {
            const Vec2 n = h->planeNormal(), t = leftNormal(n), p = h->point();
            c.polyline({p - far * t, p + far * t, p + far * t - far * n, p - far * t - far * n}, true);
        } else if (auto b = dynamic_cast<const BoxCollider*>(col.get())) {
            const Box& x = b->box();
            c.polyline({x.min, Vec2(x.max.x(), x.min.y()), x.max, Vec2(x.min.x(), x.max.y())}, true);
        } else if (auto ci = dynamic_cast<const CircleCollider*>(col.get())) {
            const Vec2 q = c.toPixels(ci->center());
            cairo_new_sub_path(c.cr());
            cairo_arc(c.cr(), q.x(), q.y(), ci->radius() * c.scale(), 0, 2 * std::numbers::pi);
        }
        cairo_fill(c.cr());
    }
}

// Returns the stress scale used (Pa).
double drawParticles(const Canvas& c, const Solver2D& solver) {
    const Particles& P = solver.particles();
    std::vector<double> s1(P.size());
    for (size_t p = 0; p < P.size(); ++p) s1[p] = largestPrincipal(solver.cauchyStress(p));
    std::vector<double> magnitude(s1.size());
    std::transform(s1.begin(), s1.end(), magnitude.begin(), [](double v) { return std::abs(v); });
    const size_t k = std::min(magnitude.size() - 1, size_t(0.99 * double(magnitude.size())));
    std::nth_element(magnitude.begin(), magnitude.begin() + long(k), magnitude.end());
    const double scale = magnitude[k] > 0 ? magnitude[k] : 1.0;
    const double side = std::max(1.0, solver.particleSpacing() * c.scale());
    // Without anti-aliasing neighbouring squares meet without seams.
    cairo_set_antialias(c.cr(), CAIRO_ANTIALIAS_NONE);
    for (size_t p = 0; p < P.size(); ++p) {
        const Vec2 q = c.toPixels(P.x[p]);
        c.colour(stressColour(s1[p] / scale));
        cairo_rectangle(c.cr(), q.x() - 0.5 * side, q.y() - 0.5 * side, side, side);
        cairo_fill(c.cr());
    }
    cairo_set_antialias(c.cr(), CAIRO_ANTIALIAS_DEFAULT);
    return scale;
}

void drawCracks(const Canvas& c, const Solver2D& solver) {
    cairo_set_line_join(c.cr(), CAIRO_LINE_JOIN_ROUND);
    for (const Crack& crack : solver.cracks()) {
        std::vector<Vec2> above, below;
        for (size_t k = 0; k < crack.points.size(); ++k) {
            above.push_back(crack.points[k] + crack.above[k]);
            below.push_back(crack.points[k] + crack.below[k]);
        }
        // The gap between the surfaces, filled, then the surfaces themselves.
        std::vector<Vec2> gap = above;
        gap.insert(gap.end(), below.rbegin(), below.rend());
        c.colour({0.1, 0.1, 0.12});
        c.polyline(gap, true);
        cairo_fill(c.cr());
        cairo_set_line_width(c.cr(), 2.0);
        c.polyline(above, false);
        cairo_stroke(c.cr());
        c.polyline(below, false);
        cairo_stroke(c.cr());
    }
    for (const TipResult& t : solver.tips()) {
        if (t.contour.size() > 1) {
            c.colour({0.1, 0.6, 0.2});
            cairo_set_line_width(c.cr(), 1.5);
            c.polyline(t.contour, false);
            cairo_stroke(c.cr());
        }
        const Vec2 q = c.toPixels(t.position);
        c.colour({1.0, 0.55, 0.0});
        cairo_new_sub_path(c.cr());
        cairo_arc(c.cr(), q.x(), q.y(), 4, 0, 2 * std::numbers::pi);
        cairo_fill(c.cr());
    }
}

void drawTitle(const Canvas& c, const std::string& title, double stressScale) {
    c.colour({0.13, 0.15, 0.18});
    cairo_select_font_face(c.cr(), "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
    cairo_set_font_size(c.cr(), 15);
    cairo_move_to(c.cr(), 12, 25);
    char scale[96];
    std::snprintf(scale, sizeof scale, "   ·   σ₁ colour scale ±%.3g Pa", stressScale);
    cairo_show_text(c.cr(), (title + scale).c_str());
    // The colour bar: blue (compression) to red (tension).
    const int x0 = c.width() - 172, y0 = 14;
    for (int i = 0; i < 160; ++i) {
        c.colour(stressColour((i - 79.5) / 79.5));
        cairo_rectangle(c.cr(), x0 + i, y0, 1, 14);
        cairo_fill(c.cr());
    }
}

} // namespace

MpmPicture::MpmPicture(const Solver2D& solver, int width, int height) : width_(width), height_(height) {
    const Box view = viewBox(solver);
    centre_ = 0.5 * (view.min + view.max);
    const Vec2 size = view.max - view.min;
    scale_ = std::min(width / size.x(), (height - kTitleBand) / size.y());
}

void MpmPicture::write(const std::filesystem::path& path, const Solver2D& solver, const std::string& title) const {
    const Canvas c(width_, height_, centre_, scale_);
    cairo_set_source_rgb(c.cr(), 1, 1, 1);
    cairo_paint(c.cr());
    drawColliders(c, solver);
    const double stressScale = drawParticles(c, solver);
    drawCracks(c, solver);
    drawTitle(c, title, stressScale);
    c.save(path);
}

} // namespace shatter::mpm::demo
