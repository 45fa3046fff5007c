#include "demos/runner/PngRenderer.h"

#include <cairo.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <optional>
#include <stdexcept>

namespace shatter::demo {

namespace {

constexpr int kTitleBand = 56; // pixels above the scene kept for the title line

struct Rgb {
    double r, g, b;
};

const Rgb kBackground{0.87, 0.89, 0.92};
const Rgb kFloorLight{0.80, 0.82, 0.85};
const Rgb kFloorDark{0.70, 0.72, 0.76};
const Rgb kText{0.13, 0.15, 0.18};

// Towards the light: above, a little to the camera's left and in front, so the three
// visible sides of a box get three different shades and shadows fall behind the objects.
Eigen::Vector3d lightDirection() { return Eigen::Vector3d(-0.25, 1.0, 0.55).normalized(); }

Rgb mix(Rgb a, Rgb b, double t) { return {a.r + (b.r - a.r) * t, a.g + (b.g - a.g) * t, a.b + (b.b - a.b) * t}; }
Rgb scaled(Rgb c, double k) { return {std::min(1.0, c.r * k), std::min(1.0, c.g * k), std::min(1.0, c.b * k)}; }

// A hue from the name (FNV-1a): a body keeps its colour across frames, runs and machines,
// and the fragments of a broken body ("door.7", "door.8") get distinct colours.
Rgb colourOf(const std::string& name) {
    std::uint32_t h = 2166136261u;
    for (unsigned char c : name) h = (h ^ c) * 16777619u;
    const double hue = (h % 3600) / 600.0; // sextant in [0, 6)
    const double s = 0.50, v = 0.90;
    const double f = hue - std::floor(hue), p = v * (1 - s), q = v * (1 - s * f), t = v * (1 - s * (1 - f));
    switch (int(hue)) {
    case 0: return {v, t, p};
    case 1: return {q, v, p};
    case 2: return {p, v, t};
    case 3: return {p, q, v};
    case 4: return {t, p, v};
    default: return {v, p, q};
    }
}

void setColour(cairo_t* cr, Rgb c, double alpha = 1.0) { cairo_set_source_rgba(cr, c.r, c.g, c.b, alpha); }

double smoothstep(double a, double b, double x) {
    const double t = std::clamp((x - a) / (b - a), 0.0, 1.0);
    return t * t * (3 - 2 * t);
}

// 1, 2 or 5 times a power of ten: floor squares a person can read as a scale.
double niceStep(double x) {
    const double p = std::pow(10.0, std::floor(std::log10(x)));
    const double m = x / p;
    return (m < 1.5 ? 1 : m < 3.5 ? 2 : m < 7.5 ? 5 : 10) * p;
}

std::optional<double> groundHeight(const std::vector<NamedMesh>& meshes) {
    std::optional<double> height;
    for (const NamedMesh& m : meshes)
        if (m.ground)
            for (const auto& p : m.mesh.positions) height = std::max(height.value_or(-INFINITY), p.y());
    return height;
}

struct Bounds {
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(INFINITY), hi = Eigen::Vector3d::Constant(-INFINITY);
    bool empty() const { return !(lo.array() <= hi.array()).all(); }
};

Bounds objectBounds(const std::vector<NamedMesh>& meshes) {
    Bounds b;
    for (const NamedMesh& m : meshes)
        if (!m.ground)
            for (const auto& p : m.mesh.positions)
                if (p.allFinite()) {
                    b.lo = b.lo.cwiseMin(p);
                    b.hi = b.hi.cwiseMax(p);
                }
    return b;
}

// The floor patch drawn under the objects: a checkerboard that fades into the background.
struct Floor {
    double height;
    Eigen::Vector2d centre; // x, z
    double radius;
    double cell;
};

Floor floorUnder(const Bounds& b, double height) {
    Floor f{height, Eigen::Vector2d::Zero(), 2.0, 0.5};
    if (b.empty()) return f;
    f.centre = Eigen::Vector2d(0.5 * (b.lo.x() + b.hi.x()), 0.5 * (b.lo.z() + b.hi.z()));
    const double reach = std::max({0.5 * (b.hi.x() - b.lo.x()), 0.5 * (b.hi.z() - b.lo.z()), b.hi.y() - height, 0.25});
    f.radius = 3.0 * reach;
    f.cell = niceStep(f.radius / 5);
    return f;
}

// Sutherland-Hodgman against the near plane, in camera coordinates.
std::vector<Eigen::Vector3d> clipNear(const std::vector<Eigen::Vector3d>& polygon, double near) {
    std::vector<Eigen::Vector3d> out;
    for (size_t i = 0; i < polygon.size(); ++i) {
        const Eigen::Vector3d& a = polygon[i];
        const Eigen::Vector3d& b = polygon[(i + 1) % polygon.size()];
        const bool aIn = a.z() >= near, bIn = b.z() >= near;
        if (aIn) out.push_back(a);
        if (aIn != bIn) out.push_back(a + (b - a) * ((near - a.z()) / (b.z() - a.z())));
    }
    return out;
}

// Projects a world polygon; empty when it is entirely behind the camera.
std::vector<Eigen::Vector2d> project(const Camera& camera, const std::vector<Eigen::Vector3d>& world) {
    std::vector<Eigen::Vector3d> cameraSpace;
    cameraSpace.reserve(world.size());
    for (const auto& p : world) cameraSpace.push_back(camera.toCamera(p));
    std::vector<Eigen::Vector2d> pixels;
    for (const auto& q : clipNear(cameraSpace, camera.nearDepth())) pixels.push_back(camera.toPixel(q));
    if (pixels.size() < 3) pixels.clear();
    return pixels;
}

void trace(cairo_t* cr, const std::vector<Eigen::Vector2d>& pixels) {
    cairo_new_path(cr);
    for (const auto& p : pixels) cairo_line_to(cr, p.x(), p.y());
    cairo_close_path(cr);
}

void drawFloor(cairo_t* cr, const Camera& camera, const Floor& f) {
    const long i0 = long(std::floor((f.centre.x() - f.radius) / f.cell)), i1 = long(std::ceil((f.centre.x() + f.radius) / f.cell));
    const long j0 = long(std::floor((f.centre.y() - f.radius) / f.cell)), j1 = long(std::ceil((f.centre.y() + f.radius) / f.cell));
    cairo_set_line_width(cr, 1.0);
    for (long i = i0; i < i1; ++i)
        for (long j = j0; j < j1; ++j) {
            const double x = i * f.cell, z = j * f.cell;
            const double distance = (Eigen::Vector2d(x + 0.5 * f.cell, z + 0.5 * f.cell) - f.centre).norm();
            if (distance > f.radius) continue;
            const auto pixels = project(camera, {{x, f.height, z}, {x, f.height, z + f.cell}, {x + f.cell, f.height, z + f.cell},
                                                 {x + f.cell, f.height, z}});
            if (pixels.empty()) continue;
            const Rgb checker = (i + j) % 2 == 0 ? kFloorLight : kFloorDark;
            setColour(cr, mix(checker, kBackground, smoothstep(0.45 * f.radius, f.radius, distance)));
            trace(cr, pixels);
            cairo_fill_preserve(cr);
            cairo_stroke(cr); // same colour: closes the hairline seams anti-aliasing leaves between cells
        }
}

// One flat-coloured shadow for everything, cast straight along the light onto the floor.
void drawShadows(cairo_t* cr, const Camera& camera, const std::vector<NamedMesh>& meshes, double floorHeight) {
    const Eigen::Vector3d light = lightDirection();
    cairo_push_group(cr);
    cairo_set_source_rgb(cr, 0, 0, 0);
    cairo_set_line_width(cr, 1.0);
    std::vector<Eigen::Vector3d> world;
    for (const NamedMesh& m : meshes) {
        if (m.ground) continue;
        for (const auto& face : m.mesh.faces) {
            world.clear();
            for (int v : face) {
                const Eigen::Vector3d& p = m.mesh.positions[size_t(v)];
                world.push_back(p - light * (std::max(p.y() - floorHeight, 0.0) / light.y()));
                world.back().y() = floorHeight;
            }
            if (!std::all_of(world.begin(), world.end(), [](const auto& p) { return p.allFinite(); })) continue;
            const auto pixels = project(camera, world);
            if (pixels.empty()) continue;
            trace(cr, pixels);
            cairo_fill_preserve(cr);
            cairo_stroke(cr); // without it, anti-aliased shared edges show as light seams
        }
    }
    cairo_pop_group_to_source(cr);
    cairo_paint_with_alpha(cr, 0.18);
}

struct Polygon {
    std::vector<Eigen::Vector2d> pixels;
    double depth;
    Rgb fill;
    bool outlined;
};

// Newell's normal: robust for slightly non-planar polygons; zero for degenerate ones.
Eigen::Vector3d newellNormal(const std::vector<Eigen::Vector3d>& p) {
    Eigen::Vector3d n = Eigen::Vector3d::Zero();
    for (size_t i = 0; i < p.size(); ++i) n += p[i].cross(p[(i + 1) % p.size()]);
    return n.norm() > 0 ? n.normalized() : n;
}

std::vector<Polygon> shadedPolygons(const std::vector<NamedMesh>& meshes, const Camera& camera) {
    const Eigen::Vector3d light = lightDirection();
    std::vector<Polygon> polygons;
    std::vector<Eigen::Vector3d> world;
    for (const NamedMesh& m : meshes) {
        if (m.ground) continue;
        const Rgb surface = colourOf(m.name);
        // Crack faces (fracture opened them inside the solid) in the pale colour of fresh
        // broken material, so the break shows.
        const Rgb crack = mix(surface, Rgb{1.0, 1.0, 0.96}, 0.75);
        for (size_t f = 0; f < m.mesh.faces.size(); ++f) {
            const auto& face = m.mesh.faces[f];
            const Rgb base = m.mesh.isCrackFace(f) ? crack : surface;
            world.clear();
            for (int v : face) world.push_back(m.mesh.positions[size_t(v)]);
            if (world.size() < 3 || !std::all_of(world.begin(), world.end(), [](const auto& p) { return p.allFinite(); }))
                continue;
            Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
            for (const auto& p : world) centroid += p;
            centroid /= double(world.size());
            Eigen::Vector3d n = newellNormal(world);
            const Eigen::Vector3d view = (camera.eye() - centroid).normalized();
            if (n.dot(view) < 0) n = -n; // open surfaces are seen from both sides
            const double shade = 0.38 + 0.55 * std::max(0.0, n.dot(light)) + 0.12 * n.dot(view);
            Polygon polygon{project(camera, world), camera.toCamera(centroid).z(), scaled(base, shade), m.outlined};
            if (!polygon.pixels.empty()) polygons.push_back(std::move(polygon));
        }
    }
    // Far to near; stable so that equal depths keep mesh order and the picture is reproducible.
    std::stable_sort(polygons.begin(), polygons.end(), [](const Polygon& a, const Polygon& b) { return a.depth > b.depth; });
    return polygons;
}

double pixelSpan(const std::vector<Eigen::Vector2d>& pixels) {
    Eigen::Vector2d lo = pixels[0], hi = pixels[0];
    for (const auto& p : pixels) {
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
    }
    return (hi - lo).maxCoeff();
}

void drawPolygons(cairo_t* cr, const std::vector<Polygon>& polygons) {
    cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
    for (const Polygon& p : polygons) {
        trace(cr, p.pixels);
        setColour(cr, p.fill);
        cairo_fill_preserve(cr);
        cairo_set_line_width(cr, 0.8);
        cairo_stroke_preserve(cr); // covers the seams between neighbouring polygons
        // Edges of polygons only a few pixels wide would just darken the surface.
        if (p.outlined && pixelSpan(p.pixels) >= 6.0) {
            setColour(cr, scaled(p.fill, 0.35), 0.6);
            cairo_set_line_width(cr, 0.7);
            cairo_stroke_preserve(cr);
        }
        cairo_new_path(cr);
    }
}

void drawTitle(cairo_t* cr, const Picture& picture, const std::string& scale) {
    setColour(cr, kText);
    cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_BOLD);
    cairo_set_font_size(cr, 22);
    cairo_move_to(cr, 24, 36);
    cairo_show_text(cr, picture.title.c_str());
    cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
    cairo_set_font_size(cr, 15);
    double x, y;
    cairo_get_current_point(cr, &x, &y);
    cairo_move_to(cr, x + 16, 36);
    std::string caption = picture.caption;
    if (!scale.empty()) caption += (caption.empty() ? "" : "  ·  ") + scale;
    cairo_show_text(cr, caption.c_str());
}

std::string floorScale(const Floor& f) {
    char text[64];
    std::snprintf(text, sizeof text, "floor squares %g m", f.cell);
    return text;
}

} // namespace

Camera frameScene(const std::vector<NamedMesh>& meshes, const Picture& picture) {
    std::vector<Eigen::Vector3d> points;
    for (const NamedMesh& m : meshes)
        if (!m.ground) points.insert(points.end(), m.mesh.positions.begin(), m.mesh.positions.end());
    // With a floor, the objects' footprint and the shadows they cast belong in the picture too.
    if (const auto height = groundHeight(meshes)) {
        const Bounds b = objectBounds(meshes);
        if (!b.empty()) {
            const double pad = 0.15 * std::max((b.hi - b.lo).maxCoeff(), 0.2);
            for (double x : {b.lo.x() - pad, b.hi.x() + pad})
                for (double z : {b.lo.z() - pad, b.hi.z() + pad}) points.emplace_back(x, *height, z);
        } else {
            for (double x : {-1.0, 1.0})
                for (double z : {-1.0, 1.0}) points.emplace_back(x, *height, z);
        }
    }
    return Camera::framing(points, picture.width, picture.height, kTitleBand);
}

void renderPng(const std::vector<NamedMesh>& meshes, const Camera& camera, const Picture& picture,
               const std::filesystem::path& path) {
    std::unique_ptr<cairo_surface_t, void (*)(cairo_surface_t*)> surface(
        cairo_image_surface_create(CAIRO_FORMAT_RGB24, picture.width, picture.height), &cairo_surface_destroy);
    std::unique_ptr<cairo_t, void (*)(cairo_t*)> context(cairo_create(surface.get()), &cairo_destroy);
    cairo_t* cr = context.get();
    setColour(cr, kBackground);
    cairo_paint(cr);

    std::string scale;
    if (const auto height = groundHeight(meshes)) {
        const Floor floor = floorUnder(objectBounds(meshes), *height);
        drawFloor(cr, camera, floor);
        drawShadows(cr, camera, meshes, *height);
        scale = floorScale(floor);
    }
    drawPolygons(cr, shadedPolygons(meshes, camera));
    drawTitle(cr, picture, scale);

    cairo_surface_flush(surface.get());
    const cairo_status_t status = cairo_surface_write_to_png(surface.get(), path.c_str());
    if (status != CAIRO_STATUS_SUCCESS)
        throw std::runtime_error(path.string() + ": cannot write PNG: " + cairo_status_to_string(status));
}

} // namespace shatter::demo
