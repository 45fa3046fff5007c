#pragma once
// The one source of randomness of every module: SplitMix64, written out here so that the
// same seed gives the same numbers with every compiler and standard library (std::
// distributions are implementation-defined). Each body or pattern owns one, seeded.
#include <cstdint>

namespace shatter {

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
    // Uniform integer in [0, n), n > 0; the multiply-shift map's bias is below 2^-32 for any
    // n a lattice has.
    int below(int n) { return int((next() >> 32) * std::uint64_t(n) >> 32); }

private:
    std::uint64_t state_;
};

} // namespace shatter
