#include <shatter/plugin/oriented/SimdLanes.h>

namespace shatter::oriented {

bool simdPathAvailable(SimdPath path) {
    if (path == SimdPath::Portable) return true;
    if (path != SimdPath::Avx2) return false; // not one of the two paths
#if SHATTER_HAS_AVX2_PATH
    // __builtin_cpu_init first: this may run in a static initialiser before libgcc's own.
    static const bool avx2 = (__builtin_cpu_init(), __builtin_cpu_supports("avx2"));
    return avx2;
#else
    return false;
#endif
}

SimdPath fastestSimdPath() {
    static const SimdPath path = simdPathAvailable(SimdPath::Avx2) ? SimdPath::Avx2 : SimdPath::Portable;
    return path;
}

} // namespace shatter::oriented
