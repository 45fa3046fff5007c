#pragma once
// Which hand-written SIMD paths this processor runs, asked in one place.
//
// The plugin's default build is portable (SSE2 on x86-64). A few hot loops also have an AVX2
// copy, compiled with [[gnu::target("avx2")]] and chosen at run time, so one binary runs on any
// x86-64 and uses AVX2 where the processor has it. A module's environment variable
// (SHATTER_LATTICE_KERNEL) set to "portable" makes its loops take the portable path: the tests
// run the suites both ways, and timings compare them.
#include <cstdlib>
#include <string_view>

// GCC/Clang on x86: where __builtin_cpu_supports and [[gnu::target]] exist.
#if (defined(__x86_64__) || defined(__i386__)) && defined(__GNUC__)
#define SHATTER_X86_SIMD 1
#else
#define SHATTER_X86_SIMD 0
#endif

namespace shatter {

// Whether this processor runs AVX2 (false off x86 or without GCC/Clang). Asked once.
inline bool processorRunsAvx2() {
#if SHATTER_X86_SIMD
    // __builtin_cpu_init first: this may run in a static initialiser before libgcc's own.
    static const bool avx2 = (__builtin_cpu_init(), __builtin_cpu_supports("avx2"));
    return avx2;
#else
    return false;
#endif
}

// Whether the environment variable `name` asks for the portable paths ("portable").
inline bool portablePathForced(const char* name) {
    const char* value = std::getenv(name);
    return value && std::string_view(value) == "portable";
}

} // namespace shatter
