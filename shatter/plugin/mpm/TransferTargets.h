#pragma once
// The two transfer loops (ParticleToGrid.cpp, GridToParticle.cpp), most of the solver's time,
// are compiled twice: for x86-64-v3 (AVX2 and FMA), marked TRANSFER_X86_64_V3, and for the
// build's own target (plain x86-64 by default); runsX86_64_v3() tells which copy this CPU
// runs. The x86-64-v3 copy works the cubic kernel's far-from-crack particles a grid node at a
// time in Double4 vectors (Double4.h) and has fused multiply-adds; the generic copy keeps the
// scalar loops, because GCC lowers 256-bit vectors for SSE2 through memory (the vector code
// ran 3.8 times slower there). A generic build thus still runs on every x86-64 CPU. The
// per-particle work is inlined (always_inline) into the marked loops, so that it is compiled
// in both ways.
//
// Rounding: a fused multiply-add rounds once where a multiply and an add round twice, and the
// vector path sums in another order, so the two copies differ in the last bits. Results stay
// bit-identical run to run and for any thread count on one machine, but one binary gives
// other bits on a CPU with and a CPU without AVX2/FMA, and where a crack tip's growth is on
// its threshold, another crack path.
#if defined(__x86_64__) && defined(__GNUC__)
#define TRANSFER_X86_64_V3 [[gnu::target("arch=x86-64-v3")]]
#else
#define TRANSFER_X86_64_V3
#endif
// A third copy of both loops, for x86-64-v4 (AVX-512), marked TRANSFER_X86_64_V4, works on
// Double8s (Double4.h): the scatter adds two grid nodes per instruction, the gather samples
// two adjacent far particles at once. The same operations per node and per particle as the
// x86-64-v3 copy, so the same bits (tested). GCC only (clang 14 knows neither level name).
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define TRANSFER_HAS_X86_64_V4 1
#define TRANSFER_X86_64_V4 [[gnu::target("arch=x86-64-v4")]]
#else
#define TRANSFER_HAS_X86_64_V4 0
#define TRANSFER_X86_64_V4
#endif

namespace shatter::mpm {

// Set by tests and by `shatter-bench-mpm --generic`: the generic copy even on an x86-64-v3
// CPU, to check it against the other and to time it. Read between substeps.
inline bool& forceGenericTransfers() {
    static bool force = false;
    return force;
}

inline bool runsX86_64_v3() {
#if defined(__x86_64__) && defined(__GNUC__)
    // The level's features one by one: GCC 12 knows the level name "x86-64-v3", clang 14
    // does not (an invalid feature string there), nor "f16c", "lzcnt", "movbe" or "xsave". Every
    // CPU with AVX2, FMA and BMI2 (Intel since Haswell, AMD since Excavator/Zen) has those too.
    static const bool cpu = [] {
        __builtin_cpu_init();
        return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") && __builtin_cpu_supports("bmi") &&
               __builtin_cpu_supports("bmi2") && __builtin_cpu_supports("avx") && __builtin_cpu_supports("sse4.2") &&
               __builtin_cpu_supports("popcnt");
    }();
    return cpu && !forceGenericTransfers();
#else
    return false;
#endif
}

// Set by tests and by `shatter-bench-mpm --no-avx512`: the x86-64-v3 copies even on an
// x86-64-v4 CPU, to check that both give the same bits and to time them. Read between substeps.
inline bool& forceX86_64_v3Transfers() {
    static bool force = false;
    return force;
}

// Whether this CPU runs the x86-64-v4 copies: x86-64-v3 and AVX-512 (F, VL, BW, DQ, CD: the
// level's set).
inline bool runsX86_64_v4() {
#if TRANSFER_HAS_X86_64_V4
    static const bool cpu = [] {
        __builtin_cpu_init();
        return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") &&
               __builtin_cpu_supports("avx512bw") && __builtin_cpu_supports("avx512dq") &&
               __builtin_cpu_supports("avx512cd");
    }();
    return cpu && runsX86_64_v3() && !forceX86_64_v3Transfers();
#else
    return false;
#endif
}

} // namespace shatter::mpm
