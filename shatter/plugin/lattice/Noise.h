#pragma once
// Seeded 3D gradient noise (Perlin's "improved noise", 2002: quintic fade, 12 edge gradients)
// and its use on link strengths (source 002 §2: "three-dimensional noise functions provide a
// way to change the connection strength of the objects procedurally").
//
// Written here rather than taken from Debian's libnoise-dev (LGPL, unmaintained since 2007):
// it is forty lines, and owning it keeps the lattice free of a run-time dependency and its
// output bit-identical for a seed on every platform (see third_party_notes/noise.md).
#include <shatter/plugin/lattice/Lattice.h>

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <string>

namespace shatter::lattice {

class PerlinNoise {
public:
    // The permutation table is shuffled by `seed` (Fisher-Yates with the lattice's Random).
    explicit PerlinNoise(std::uint64_t seed);
    // Gradient noise in about [-1, 1], zero at integer points, period 256 along each axis.
    double operator()(const Eigen::Vector3d& p) const;
    // Sum of `octaves` layers, each at twice the frequency and half the amplitude of the
    // last, normalised so the result stays in about [-1, 1].
    double fractal(const Eigen::Vector3d& p, int octaves) const;

private:
    std::array<int, 512> perm_;
};

struct NoiseSettings {
    bool enabled = false;
    double amplitude = 0.6; // strength × (1 + amplitude · noise), noise in [-1, 1]; >= 0
    double scale = 0.3;     // m: size of the noise features (one unit of the noise grid)
    int octaves = 3;        // 1-8
    double floor = 0.05;    // smallest multiplier, so no link starts at zero strength

    void check(const std::string& body) const;
};

// Multiplies the base and current strength of every link by max(floor, 1 + amplitude ·
// noise(face centre / scale)). Same seed, same strengths.
void applyNoise(Lattice& lattice, const NoiseSettings& settings, std::uint64_t seed);

} // namespace shatter::lattice
