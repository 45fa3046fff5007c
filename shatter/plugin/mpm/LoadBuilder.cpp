#include <shatter/plugin/mpm/LoadBuilder.h>

#include <shatter/plugin/common/InputError.h>

#include <cmath>
#include <map>

namespace shatter::mpm {

namespace {

std::string where(const Scene& scene, const std::string& key) {
    return (scene.source.empty() ? std::string() : scene.source + ": ") + key;
}

ParticleLoad tractionLoad(const Scene& scene, const SeededParticles& seeded, const Load& load) {
    const double h = seeded.spacing;
    std::map<std::uint32_t, Vec2> share; // ordered, so the load lists are deterministic
    for (const Body& body : scene.bodies) {
        const std::vector<Vec2> loop = body.shape.outline();
        for (size_t e = 0; e < loop.size(); ++e) {
            const Vec2 a = loop[e], b = loop[(e + 1) % loop.size()];
            const double length = (b - a).norm();
            const int pieces = std::max(1, int(std::ceil(length / (0.25 * h))));
            for (int k = 0; k < pieces; ++k) {
                const Vec2 mid = a + (b - a) * ((k + 0.5) / pieces);
                if (!load.region.contains(mid)) continue;
                // Outline pieces inside other bodies (interfaces) have no outer particle near.
                const long p = seeded.nearestSurface(mid, 1.5 * h);
                if (p < 0) continue;
                auto [it, added] = share.try_emplace(std::uint32_t(p), Vec2::Zero());
                it->second += load.value * (length / pieces);
            }
        }
    }
    ParticleLoad out;
    for (const auto& [p, f] : share) {
        out.particle.push_back(p);
        out.force.push_back(f);
    }
    return out;
}

ParticleLoad forceLoad(const Particles& particles, const Load& load) {
    ParticleLoad out;
    double mass = 0;
    for (size_t p = 0; p < particles.size(); ++p)
        if (load.region.contains(particles.x0[p])) {
            out.particle.push_back(std::uint32_t(p));
            mass += particles.mass[p];
        }
    for (std::uint32_t p : out.particle) out.force.push_back(load.value * (particles.mass[p] / mass));
    return out;
}

} // namespace

std::vector<ParticleLoad> buildLoads(const Scene& scene, const SeededParticles& seeded) {
    std::vector<ParticleLoad> loads;
    for (size_t k = 0; k < scene.loads.size(); ++k) {
        const Load& load = scene.loads[k];
        ParticleLoad built = load.kind == Load::Kind::Traction ? tractionLoad(scene, seeded, load)
                                                               : forceLoad(seeded.particles, load);
        if (built.particle.empty())
            throw InputError(where(scene, "loads[" + std::to_string(k) + "].region") +
                             (load.kind == Load::Kind::Traction ? ": contains no part of any body's outline"
                                                                : ": contains no particle"));
        built.ramp = load.ramp;
        loads.push_back(std::move(built));
    }
    return loads;
}

void markFixedParticles(const Scene& scene, Particles& particles) {
    for (size_t k = 0; k < scene.fixed.size(); ++k) {
        bool any = false;
        for (size_t p = 0; p < particles.size(); ++p)
            if (scene.fixed[k].contains(particles.x0[p])) {
                particles.fixed[p] = 1;
                any = true;
            }
        if (!any) throw InputError(where(scene, "fixed[" + std::to_string(k) + "]") + ": contains no particle");
    }
}

void applyLoads(const std::vector<ParticleLoad>& loads, double time, std::vector<Vec2>& force) {
    std::fill(force.begin(), force.end(), Vec2::Zero());
    for (const ParticleLoad& load : loads) {
        const double f = load.factor(time);
        for (size_t k = 0; k < load.particle.size(); ++k) force[load.particle[k]] += f * load.force[k];
    }
}

} // namespace shatter::mpm
