#pragma once
// The fracture module's one source of randomness: SplitMix64, written out so that the same
// seed gives the same pattern with every compiler and standard library (std:: distributions
// are implementation-defined). Same generator as lattice/Random.h; modules may not include
// each other, so each keeps its own ten lines.
#include <cstdint>

namespace shatter::fracture {

class Random {
public:
    explicit Random(std::uint64_t seed) : state_(seed) {}

    std::uint64_t next() {
        std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return z ^ (z >> 31);
    }
    // Uniform in [0, 1), 53 random bits.
    double uniform() { return double(next() >> 11) * 0x1.0p-53; }
    // Uniform in [lo, hi).
    double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }

private:
    std::uint64_t state_;
};

} // namespace shatter::fracture
