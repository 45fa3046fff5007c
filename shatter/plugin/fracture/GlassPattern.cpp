#include <shatter/plugin/fracture/FracturePattern.h>

#include <shatter/plugin/fracture/Random.h>

#include <cmath>
#include <numbers>

namespace shatter::fracture {

namespace {

// Right prism through z in [-height, height] under a convex polygon, counter-clockwise
// seen from +z.
geometry::ConvexPolyhedron prism(const std::vector<Eigen::Vector2d>& polygon, double height, int index) {
    const int n = int(polygon.size());
    std::vector<Eigen::Vector3d> vertices;
    for (const auto& p : polygon) vertices.emplace_back(p.x(), p.y(), -height);
    for (const auto& p : polygon) vertices.emplace_back(p.x(), p.y(), height);
    std::vector<std::vector<int>> faces;
    std::vector<int> top, bottom;
    for (int i = 0; i < n; ++i) {
        top.push_back(n + i);
        bottom.push_back(n - 1 - i);
        faces.push_back({i, (i + 1) % n, n + (i + 1) % n, n + i});
    }
    faces.push_back(top);
    faces.push_back(bottom);
    std::vector<int> ids(vertices.size());
    for (size_t i = 0; i < ids.size(); ++i) ids[i] = int(i);
    return geometry::ConvexPolyhedron::create(std::move(vertices), std::move(faces), std::move(ids),
                                              "glass pattern cell " + std::to_string(index));
}

} // namespace

FracturePattern glassPattern(const GlassPatternSettings& settings, std::uint64_t seed) {
    settings.check("glass pattern");
    Random random(seed);
    const int sectors = settings.sectors;
    const int rings = settings.rings;
    std::vector<double> ringRadius(static_cast<size_t>(rings));
    for (int k = 0; k < rings; ++k) ringRadius[size_t(k)] = settings.firstRing * std::pow(settings.growth, k);
    auto width = [&](int k) { return ringRadius[size_t(k)] - (k > 0 ? ringRadius[size_t(k - 1)] : 0.0); };

    // Sector boundaries and ring corners, each drawn once and shared by the cells that meet
    // there, so that neighbouring cells have identical faces.
    const double sectorAngle = 2.0 * std::numbers::pi / sectors;
    std::vector<double> angle(static_cast<size_t>(sectors));
    for (int s = 0; s < sectors; ++s) angle[size_t(s)] = sectorAngle * (s + 0.5 * settings.jitter * random.uniform(-1.0, 1.0));
    std::vector<Eigen::Vector2d> corner(static_cast<size_t>(rings * sectors));
    for (int k = 0; k < rings; ++k) {
        // Less than half the narrower neighbouring ring, so rings never cross.
        const double amplitude = settings.jitter * std::min(width(k), k + 1 < rings ? width(k + 1) : width(k));
        for (int s = 0; s < sectors; ++s) {
            const double r = ringRadius[size_t(k)] + amplitude * random.uniform(-1.0, 1.0);
            corner[size_t(k * sectors + s)] = r * Eigen::Vector2d(std::cos(angle[size_t(s)]), std::sin(angle[size_t(s)]));
        }
    }
    const double height = ringRadius.back() * (1.0 + settings.jitter);

    FracturePattern pattern;
    for (int k = 0; k < rings; ++k)
        for (int s = 0; s < sectors; ++s) {
            const int next = (s + 1) % sectors;
            std::vector<Eigen::Vector2d> polygon;
            if (k == 0) {
                polygon = {Eigen::Vector2d::Zero(), corner[size_t(s)], corner[size_t(next)]};
            } else {
                polygon = {corner[size_t((k - 1) * sectors + s)], corner[size_t(k * sectors + s)],
                           corner[size_t(k * sectors + next)], corner[size_t((k - 1) * sectors + next)]};
            }
            pattern.cells.push_back(prism(polygon, height, int(pattern.cells.size())));
        }
    pattern.radius = settings.radius;
    if (pattern.radius == 0.0) pattern.radius = ringRadius.back() * (1.0 + settings.jitter) + 1e-12;
    finishPattern(pattern);
    return pattern;
}

} // namespace shatter::fracture
