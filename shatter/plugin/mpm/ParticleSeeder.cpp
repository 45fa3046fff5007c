#include <shatter/plugin/mpm/ParticleSeeder.h>

#include <shatter/plugin/common/InputError.h>

#include <cmath>
#include <random>
#include <sstream>

namespace shatter::mpm {

namespace {

std::string prefix(const Scene& scene) { return scene.source.empty() ? std::string() : scene.source + ": "; }

// Lattice sites of body b, written into `owner` (later bodies overwrite).
void rasterise(const Body& body, int b, double h, std::map<std::pair<long, long>, int>& owner) {
    const Box box = body.shape.bounds();
    const long i0 = long(std::floor(box.min.x() / h - 0.5)), i1 = long(std::ceil(box.max.x() / h - 0.5));
    const long j0 = long(std::floor(box.min.y() / h - 0.5)), j1 = long(std::ceil(box.max.y() / h - 0.5));
    for (long j = j0; j <= j1; ++j)
        for (long i = i0; i <= i1; ++i)
            if (body.shape.contains(Vec2((i + 0.5) * h, (j + 0.5) * h))) owner[{i, j}] = b;
}

} // namespace

long SeededParticles::nearestSurface(const Vec2& p, double radius) const {
    const long ci = long(std::floor(p.x() / spacing)), cj = long(std::floor(p.y() / spacing));
    const long reach = long(std::ceil(radius / spacing)) + 1;
    long best = -1;
    double bestDistance = radius * radius;
    for (long j = cj - reach; j <= cj + reach; ++j)
        for (long i = ci - reach; i <= ci + reach; ++i) {
            const auto it = lattice.find({i, j});
            if (it == lattice.end() || !surface[it->second]) continue;
            const double d = (particles.x0[it->second] - p).squaredNorm();
            if (d <= bestDistance) { // ties: the later (larger i, j) site, deterministically
                bestDistance = d;
                best = long(it->second);
            }
        }
    return best;
}

SeededParticles seedParticles(const Scene& scene) {
    SeededParticles out;
    const double h = scene.grid.dx / scene.grid.ppc;
    out.spacing = h;
    std::map<std::pair<long, long>, int> owner;
    for (size_t b = 0; b < scene.bodies.size(); ++b) rasterise(scene.bodies[b], int(b), h, owner);
    std::vector<size_t> count(scene.bodies.size(), 0);
    for (const auto& [key, b] : owner) ++count[size_t(b)];
    for (size_t b = 0; b < count.size(); ++b)
        if (count[b] == 0) {
            std::ostringstream s;
            s << prefix(scene) << "bodies[" << b << "].shape: holds no particle at spacing " << h
              << " m (grid.dx / grid.ppc), or is covered by later bodies";
            throw InputError(s.str());
        }
    std::mt19937_64 random(scene.seed);
    std::uniform_real_distribution<double> offset(-0.5, 0.5);
    for (const auto& [key, b] : owner) {
        const Body& body = scene.bodies[size_t(b)];
        const Material& m = scene.materials[size_t(body.material)];
        Vec2 x((key.first + 0.5) * h, (key.second + 0.5) * h);
        if (scene.grid.jitter > 0) {
            const double ox = offset(random), oy = offset(random);
            x += scene.grid.jitter * h * Vec2(ox, oy);
        }
        out.lattice[key] = std::uint32_t(out.particles.size());
        out.particles.add(x, body.velocity, m.rho * h * h, h * h, body.material, b);
    }
    out.surface.assign(out.particles.size(), 0);
    for (const auto& [key, p] : out.lattice) {
        const auto [i, j] = key;
        const bool inner = out.lattice.count({i - 1, j}) && out.lattice.count({i + 1, j}) &&
                           out.lattice.count({i, j - 1}) && out.lattice.count({i, j + 1});
        out.surface[p] = inner ? 0 : 1;
    }
    return out;
}

} // namespace shatter::mpm
