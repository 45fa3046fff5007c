#include <shatter/plugin/fracture/FracturePattern.h>

#include <shatter/plugin/fracture/Random.h>
#include <shatter/plugin/fracture/VoronoiCells.h>

#include <cmath>
#include <numbers>

namespace shatter::fracture {

FracturePattern voronoiPattern(const VoronoiPatternSettings& settings, std::uint64_t seed) {
    settings.check("Voronoi pattern");
    const double reach = settings.siteRadius > 0.0 ? settings.siteRadius : 1.5 * settings.radius;
    Random random(seed);
    std::vector<Eigen::Vector3d> sites;
    sites.reserve(size_t(settings.cells));
    for (int i = 0; i < settings.cells; ++i) {
        // Uniform direction on the half sphere z >= 0 (Archimedes: z uniform), then the
        // distance biased toward the impact.
        const double z = random.uniform();
        const double phi = 2.0 * std::numbers::pi * random.uniform();
        const double r = reach * std::pow(random.uniform(), settings.biasExponent);
        const double s = std::sqrt(std::max(0.0, 1.0 - z * z));
        sites.emplace_back(r * s * std::cos(phi), r * s * std::sin(phi), r * z);
    }
    geometry::Aabb box;
    box.min = Eigen::Vector3d::Constant(-2.0 * reach);
    box.max = Eigen::Vector3d::Constant(2.0 * reach);
    return voronoiCellsPattern(sites, box, settings.radius);
}

FracturePattern gridPattern(const GridPatternSettings& settings, std::uint64_t seed) {
    settings.check("grid pattern");
    const double h = settings.cellSize;
    const int n = settings.count;
    Random random(seed);
    std::vector<Eigen::Vector3d> sites;
    for (int k = 0; k < n; ++k)
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                const Eigen::Vector3d centre((i + 0.5 - 0.5 * n) * h, (j + 0.5 - 0.5 * n) * h, k * h);
                Eigen::Vector3d jitter;
                for (int a = 0; a < 3; ++a) jitter[a] = settings.jitter * h * random.uniform(-1.0, 1.0);
                sites.push_back(centre + jitter);
            }
    geometry::Aabb box;
    box.min = Eigen::Vector3d(-0.5 * n * h, -0.5 * n * h, -0.5 * h);
    box.max = Eigen::Vector3d(0.5 * n * h, 0.5 * n * h, (n - 0.5) * h);
    double radius = settings.radius;
    if (radius == 0.0) // every cell: just beyond the farthest site
        for (const auto& s : sites) radius = std::max(radius, s.norm() * (1.0 + 1e-9) + 1e-12);
    return voronoiCellsPattern(sites, box, radius);
}

} // namespace shatter::fracture
