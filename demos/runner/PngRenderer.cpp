#include "demos/runner/PngRenderer.h"

#include "demos/runner/BodyColour.h"
#include "demos/runner/DepthRaster.h"
#include "demos/runner/PngCanvas.h"
#include "demos/runner/PolygonTriangles.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>

namespace shatter::demo {

namespace {

constexpr int kTitleBand = 56; // pixels above the scene kept for the title line
constexpr int kSamples = 3;    // samples per pixel side: smooth edges at 9× the fill work

const Rgb kBackground{0.87, 0.89, 0.92};
const Rgb kFloorLight{0.80, 0.82, 0.85};
const Rgb kFloorDark{0.70, 0.72, 0.76};
constexpr double kShadow = 0.18;  // share of the floor's light a shadow takes
constexpr double kOutline = 0.6;  // how dark polygon edges are drawn (0: not at all)

// Towards the light: above, a little to the camera's left and in front, so the three
// visible sides of a box get three different shades and shadows fall behind the objects.
Eigen::Vector3d lightDirection() { return Eigen::Vector3d(-0.25, 1.0, 0.55).normalized(); }

Rgb mix(Rgb a, Rgb b, double t) { return {a.r + (b.r - a.r) * t, a.g + (b.g - a.g) * t, a.b + (b.b - a.b) * t}; }
Rgb scaled(Rgb c, double k) { return {std::min(1.0, c.r * k), std::min(1.0, c.g * k), std::min(1.0, c.b * k)}; }
std::uint32_t packed(Rgb c) { return packRgb(c.r, c.g, c.b); }
Rgb unpacked(std::uint32_t c) { return {(c >> 16 & 255) / 255.0, (c >> 8 & 255) / 255.0, (c & 255) / 255.0}; }

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

// Calls `draw(pixels, inverse depths)` for the triangles of a world triangle's visible part.
template <class Draw>
void projectTriangle(const Camera& camera, const std::array<Eigen::Vector3d, 3>& world, Draw&& draw) {
    std::vector<Eigen::Vector3d> q;
    for (const auto& p : world) q.push_back(camera.toCamera(p));
    const std::vector<Eigen::Vector3d> clipped = clipNear(q, camera.nearDepth());
    for (size_t i = 1; i + 1 < clipped.size(); ++i) {
        const std::array<const Eigen::Vector3d*, 3> c{&clipped[0], &clipped[i], &clipped[i + 1]};
        draw(std::array<Eigen::Vector2d, 3>{camera.toPixel(*c[0]), camera.toPixel(*c[1]), camera.toPixel(*c[2])},
             std::array<double, 3>{1 / c[0]->z(), 1 / c[1]->z(), 1 / c[2]->z()});
    }
}

// The floor, sample by sample: where the view ray meets the plane, checker colour fading out
// with the distance from the objects.
void drawFloor(DepthRaster& raster, const Camera& camera, const Floor& f) {
    const Eigen::Vector3d eye = camera.eye();
    if (eye.y() <= f.height) return;
    // The view ray is affine in the image point: a start and two steps, not a call per sample.
    const double step = 1.0 / raster.samples();
    const Eigen::Vector3d origin = camera.ray(Eigen::Vector2d(0.5 * step, 0.5 * step));
    const Eigen::Vector3d dx = camera.ray(Eigen::Vector2d(1.5 * step, 0.5 * step)) - origin;
    const Eigen::Vector3d dy = camera.ray(Eigen::Vector2d(0.5 * step, 1.5 * step)) - origin;
    const size_t wide = size_t(raster.samplesWide()), high = size_t(raster.samplesHigh());
    for (size_t row = 0; row < high; ++row) {
        Eigen::Vector3d ray = origin + double(row) * dy - dx;
        for (size_t s = row * wide; s < (row + 1) * wide; ++s) {
            ray += dx;
            if (!(ray.y() < 0)) continue;
            const double depth = (f.height - eye.y()) / ray.y();
            const Eigen::Vector3d p = eye + depth * ray;
            const double distance = (Eigen::Vector2d(p.x(), p.z()) - f.centre).norm();
            if (distance > f.radius) continue;
            const long i = long(std::floor(p.x() / f.cell)), j = long(std::floor(p.z() / f.cell));
            const Rgb checker = (i + j) % 2 == 0 ? kFloorLight : kFloorDark;
            raster.colour()[s] = packed(mix(checker, kBackground, smoothstep(0.45 * f.radius, f.radius, distance)));
            raster.inverseDepth()[s] = float(1 / depth);
        }
    }
}

// Every object's shadow, cast straight along the light onto the floor, darkens the floor
// samples it covers once (overlapping shadows do not add up).
void drawShadows(DepthRaster& raster, const Camera& camera, const std::vector<NamedMesh>& meshes, double floorHeight) {
    const Eigen::Vector3d light = lightDirection();
    std::vector<bool> shaded(raster.colour().size(), false);
    auto onFloor = [&](const Eigen::Vector3d& p) {
        Eigen::Vector3d s = p - light * (std::max(p.y() - floorHeight, 0.0) / light.y());
        s.y() = floorHeight;
        return s;
    };
    std::vector<Eigen::Vector3d> polygon;
    for (const NamedMesh& m : meshes) {
        if (m.ground) continue;
        for (const auto& face : m.mesh.faces) {
            polygon.clear();
            for (int v : face) polygon.push_back(m.mesh.positions[size_t(v)]);
            if (!std::all_of(polygon.begin(), polygon.end(), [](const auto& p) { return p.allFinite(); })) continue;
            for (const auto& t : polygonTriangles(polygon))
                projectTriangle(camera, {onFloor(polygon[size_t(t[0])]), onFloor(polygon[size_t(t[1])]), onFloor(polygon[size_t(t[2])])},
                                [&](const auto& pixels, const auto&) { raster.cover(pixels, [&](size_t s) { shaded[s] = true; }); });
        }
    }
    for (size_t s = 0; s < shaded.size(); ++s)
        if (shaded[s] && raster.inverseDepth()[s] > 0) raster.colour()[s] = packed(scaled(unpacked(raster.colour()[s]), 1 - kShadow));
}

// Newell's normal: robust for slightly non-planar polygons; zero for degenerate ones.
Eigen::Vector3d newellNormal(const std::vector<Eigen::Vector3d>& p) {
    Eigen::Vector3d n = Eigen::Vector3d::Zero();
    for (size_t i = 0; i < p.size(); ++i) n += p[i].cross(p[(i + 1) % p.size()]);
    return n.norm() > 0 ? n.normalized() : n;
}

double pixelSpan(const Camera& camera, const std::vector<Eigen::Vector3d>& world) {
    Eigen::Vector2d lo = Eigen::Vector2d::Constant(INFINITY), hi = Eigen::Vector2d::Constant(-INFINITY);
    for (const auto& p : world) {
        const Eigen::Vector3d q = camera.toCamera(p);
        if (q.z() < camera.nearDepth()) return INFINITY;
        const Eigen::Vector2d px = camera.toPixel(q);
        lo = lo.cwiseMin(px);
        hi = hi.cwiseMax(px);
    }
    return (hi - lo).maxCoeff();
}

// Draws every object polygon; returns, per face id, whether its edges are to be outlined.
std::vector<bool> drawObjects(DepthRaster& raster, const Camera& camera, const std::vector<NamedMesh>& meshes) {
    const Eigen::Vector3d light = lightDirection();
    std::vector<bool> outlined;
    std::vector<Eigen::Vector3d> world;
    for (const NamedMesh& m : meshes) {
        if (m.ground) continue;
        const Rgb base = bodyColour(m.name);
        for (size_t f = 0; f < m.mesh.faces.size(); ++f) {
            world.clear();
            for (int v : m.mesh.faces[f]) world.push_back(m.mesh.positions[size_t(v)]);
            if (world.size() < 3 || !std::all_of(world.begin(), world.end(), [](const auto& p) { return p.allFinite(); }))
                continue;
            Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
            for (const auto& p : world) centroid += p;
            centroid /= double(world.size());
            Eigen::Vector3d n = newellNormal(world);
            const Eigen::Vector3d view = (camera.eye() - centroid).normalized();
            if (n.dot(view) < 0) n = -n; // open surfaces are seen from both sides
            const double shade = 0.38 + 0.55 * std::max(0.0, n.dot(light)) + 0.12 * n.dot(view);
            const std::uint32_t colour = packed(scaled(m.mesh.isCrackFace(f) ? crackColour() : base, shade));
            const int id = int(outlined.size());
            // Edges of polygons only a few pixels wide would just darken the surface.
            outlined.push_back(m.outlined && pixelSpan(camera, world) >= 6.0);
            for (const auto& t : polygonTriangles(world))
                projectTriangle(camera, {world[size_t(t[0])], world[size_t(t[1])], world[size_t(t[2])]},
                                [&](const auto& pixels, const auto& inverseDepth) { raster.triangle(pixels, inverseDepth, colour, id); });
        }
    }
    return outlined;
}

// Darkens the samples along the border between two faces (or a face and what is behind
// it) where an outlined face meets it: the polygon edges that are visible, no hidden ones.
void drawOutlines(DepthRaster& raster, const std::vector<bool>& outlined) {
    const auto& face = raster.face();
    const int w = raster.samplesWide(), h = raster.samplesHigh();
    auto isOutlined = [&](int id) { return id >= 0 && outlined[size_t(id)]; };
    std::vector<size_t> edge;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const size_t s = size_t(y) * size_t(w) + size_t(x);
            const int id = face[s];
            if (!isOutlined(id)) continue;
            const bool border = (x + 1 < w && face[s + 1] != id) || (x > 0 && face[s - 1] != id) ||
                                (y + 1 < h && face[s + size_t(w)] != id) || (y > 0 && face[s - size_t(w)] != id);
            if (border) edge.push_back(s);
        }
    for (size_t s : edge) {
        const Rgb c = unpacked(raster.colour()[s]);
        raster.colour()[s] = packed(mix(c, scaled(c, 0.35), kOutline));
    }
}

std::string floorScale(const Floor& f) {
    char text[64];
    std::snprintf(text, sizeof text, "floor squares %g m", f.cell);
    return text;
}

} // namespace

std::vector<Eigen::Vector3d> framingPoints(const std::vector<NamedMesh>& meshes) {
    std::vector<Eigen::Vector3d> points;
    for (const NamedMesh& m : meshes)
        if (!m.ground) points.insert(points.end(), m.mesh.positions.begin(), m.mesh.positions.end());
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
    return points;
}

Camera frameScene(const std::vector<NamedMesh>& meshes, const Picture& picture, const std::vector<Eigen::Vector3d>& focus) {
    return Camera::framing(focus.empty() ? framingPoints(meshes) : focus, picture.width, picture.height, kTitleBand);
}

SceneImage renderScene(const std::vector<NamedMesh>& meshes, const Camera& camera, int width, int height) {
    DepthRaster raster(width, height, kSamples, packed(kBackground));
    SceneImage image{width, height, {}, {}};
    if (const auto floorHeight = groundHeight(meshes)) {
        const Floor floor = floorUnder(objectBounds(meshes), *floorHeight);
        drawFloor(raster, camera, floor);
        drawShadows(raster, camera, meshes, *floorHeight);
        image.floorScale = floorScale(floor);
    }
    drawOutlines(raster, drawObjects(raster, camera, meshes));
    image.pixels = raster.pixels();
    return image;
}

void renderPng(const std::vector<NamedMesh>& meshes, const Camera& camera, const Picture& picture,
               const std::filesystem::path& path) {
    PngCanvas canvas(picture.width, picture.height);
    const SceneImage scene = renderScene(meshes, camera, picture.width, picture.height);
    canvas.paste(scene, 0, 0);
    std::string caption = picture.caption;
    if (!scene.floorScale.empty()) caption += (caption.empty() ? "" : "  ·  ") + scene.floorScale;
    canvas.titleLine(24, 36, picture.title, caption);
    canvas.write(path);
}

} // namespace shatter::demo
