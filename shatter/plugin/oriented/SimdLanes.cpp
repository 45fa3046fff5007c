#include <shatter/plugin/oriented/SimdLanes.h>

namespace shatter::oriented {

bool simdPathAvailable(SimdPath path) {
    if (path == SimdPath::Portable) return true;
#if SHATTER_HAS_AVX2_PATH
    static const bool avx2 = __builtin_cpu_supports("avx2");
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
