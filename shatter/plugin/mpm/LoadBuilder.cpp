#include <shatter/plugin/mpm/LoadBuilder.h>

#include <shatter/plugin/common/InputError.h>
#include <shatter/plugin/mpm/Shape.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numbers>
#include <sstream>

namespace shatter::mpm {

namespace {

std::string where(const Scene& scene, const std::string& key) {
    return (scene.source.empty() ? std::string() : scene.source + ": ") + key;
}

// The four directions an outward normal is sorted into for the warning: the axis of its
// largest component.
constexpr const char* kFacingName[4] = {"+x", "-x", "+y", "-y"};
int facingIndex(const Vec2& n) {
    return std::abs(n.x()) >= std::abs(n.y()) ? (n.x() >= 0 ? 0 : 1) : (n.y() >= 0 ? 2 : 3);
}

// A traction or pressure load on the outline; `facingLength` gets the loaded length per
// direction (kFacingName).
ParticleLoad outlineLoad(const Scene& scene, const SeededParticles& seeded, const Load& load,
                         std::array<double, 4>& facingLength) {
    const double h = seeded.spacing;
    const double facingCos = std::cos(std::numbers::pi / 4);
    std::map<std::uint32_t, Vec2> share; // ordered, so the load lists are deterministic
    facingLength.fill(0);
    for (const Body& body : scene.bodies) {
        const std::vector<Vec2> loop = body.shape.outline();
        const double orientation = signedDoubleArea(loop) > 0 ? 1.0 : -1.0; // counter-clockwise: +1
        for (size_t e = 0; e < loop.size(); ++e) {
            const Vec2 a = loop[e], b = loop[(e + 1) % loop.size()];
            const double length = (b - a).norm();
            if (!(length > 0)) continue;
            const Vec2 outward = -orientation * leftNormal(b - a) / length;
            if (load.facing != Vec2::Zero() && outward.dot(load.facing) < facingCos) continue;
            const Vec2 traction = load.kind == Load::Kind::Pressure ? Vec2(-load.pressure * outward) : load.value;
            const int pieces = std::max(1, int(std::ceil(length / (0.25 * h))));
            for (int k = 0; k < pieces; ++k) {
                const Vec2 mid = a + (b - a) * ((k + 0.5) / pieces);
                if (!load.region.contains(mid)) continue;
                // Outline pieces inside other bodies (interfaces) have no outer particle near.
                const long p = seeded.nearestSurface(mid, 1.5 * h);
                if (p < 0) continue;
                auto [it, added] = share.try_emplace(std::uint32_t(p), Vec2::Zero());
                it->second += traction * (length / pieces);
                facingLength[size_t(facingIndex(outward))] += length / pieces;
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

std::vector<ParticleLoad> buildLoads(const Scene& scene, const SeededParticles& seeded,
                                     std::vector<std::string>& warnings) {
    std::vector<ParticleLoad> loads;
    for (size_t k = 0; k < scene.loads.size(); ++k) {
        const Load& load = scene.loads[k];
        const std::string key = "loads[" + std::to_string(k) + "]";
        const bool onOutline = load.kind != Load::Kind::Force;
        std::array<double, 4> facingLength{};
        ParticleLoad built = onOutline ? outlineLoad(scene, seeded, load, facingLength) : forceLoad(seeded.particles, load);
        if (built.particle.empty())
            throw InputError(where(scene, key + ".region") +
                             (onOutline ? load.facing != Vec2::Zero()
                                              ? ": contains no part of any body's outline facing the \"facing\" direction"
                                              : ": contains no part of any body's outline"
                                        : ": contains no particle"));
        if (onOutline && std::count_if(facingLength.begin(), facingLength.end(), [](double l) { return l > 0; }) > 1) {
            std::ostringstream w;
            w << where(scene, key + ".region") << ": catches outline facing different directions (";
            const char* separator = "";
            for (size_t d = 0; d < 4; ++d)
                if (facingLength[d] > 0) {
                    w << separator << facingLength[d] << " m facing " << kFacingName[d];
                    separator = ", ";
                }
            w << "); the " << (load.kind == Load::Kind::Pressure ? "pressure" : "traction")
              << " acts on all of it. Set \"facing\" to load one side only, or shrink the region";
            warnings.push_back(w.str());
        }
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
