#include <shatter/plugin/lattice/Noise.h>

#include <shatter/plugin/common/SettingCheck.h>
#include <shatter/plugin/lattice/Random.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>

namespace shatter::lattice {

namespace {

double fade(double t) { return t * t * t * (t * (t * 6.0 - 15.0) + 10.0); }
double lerp(double t, double a, double b) { return a + t * (b - a); }

// Dot product of (x, y, z) with one of the 12 cube-edge gradients picked by the hash.
double gradient(int hash, double x, double y, double z) {
    const int h = hash & 15;
    const double u = h < 8 ? x : y;
    const double v = h < 4 ? y : (h == 12 || h == 14 ? x : z);
    return ((h & 1) ? -u : u) + ((h & 2) ? -v : v);
}

} // namespace

PerlinNoise::PerlinNoise(std::uint64_t seed) {
    std::array<int, 256> p;
    std::iota(p.begin(), p.end(), 0);
    Random random(seed);
    for (int i = 255; i > 0; --i) std::swap(p[i], p[random.below(i + 1)]);
    for (int i = 0; i < 512; ++i) perm_[i] = p[i & 255];
}

double PerlinNoise::operator()(const Eigen::Vector3d& q) const {
    const double fx = std::floor(q.x()), fy = std::floor(q.y()), fz = std::floor(q.z());
    const int X = int(fx) & 255, Y = int(fy) & 255, Z = int(fz) & 255;
    const double x = q.x() - fx, y = q.y() - fy, z = q.z() - fz;
    const double u = fade(x), v = fade(y), w = fade(z);
    const int A = perm_[X] + Y, AA = perm_[A] + Z, AB = perm_[A + 1] + Z;
    const int B = perm_[X + 1] + Y, BA = perm_[B] + Z, BB = perm_[B + 1] + Z;
    return lerp(w,
                lerp(v, lerp(u, gradient(perm_[AA], x, y, z), gradient(perm_[BA], x - 1, y, z)),
                     lerp(u, gradient(perm_[AB], x, y - 1, z), gradient(perm_[BB], x - 1, y - 1, z))),
                lerp(v, lerp(u, gradient(perm_[AA + 1], x, y, z - 1), gradient(perm_[BA + 1], x - 1, y, z - 1)),
                     lerp(u, gradient(perm_[AB + 1], x, y - 1, z - 1), gradient(perm_[BB + 1], x - 1, y - 1, z - 1))));
}

double PerlinNoise::fractal(const Eigen::Vector3d& p, int octaves) const {
    double sum = 0.0, amplitude = 1.0, total = 0.0, frequency = 1.0;
    for (int o = 0; o < octaves; ++o) {
        sum += amplitude * (*this)(p * frequency);
        total += amplitude;
        amplitude *= 0.5;
        frequency *= 2.0;
    }
    return sum / total;
}

void applyNoise(Lattice& lattice, const NoiseSettings& s, std::uint64_t seed) {
    if (!s.enabled) return;
    const PerlinNoise noise(seed);
    // An offset off the integer grid, where gradient noise is always zero.
    const Eigen::Vector3d offset(0.37, 0.61, 0.13);
    for (int k = 0; k < lattice.linkCount(); ++k) {
        const double n = noise.fractal(lattice.links()[k].faceCentre / s.scale + offset, s.octaves);
        lattice.scaleStrength(k, std::max(s.floor, 1.0 + s.amplitude * n));
    }
}

void NoiseSettings::check(const std::string& body) const {
    requireNonNegative(body, "noise amplitude", amplitude);
    requirePositive(body, "noise scale", scale);
    requireSetting(octaves >= 1 && octaves <= 8, body, "noise octaves", "in [1, 8]", octaves);
    requireSetting(floor > 0.0 && floor <= 1.0, body, "noise floor", "in (0, 1]", floor);
}

} // namespace shatter::lattice
