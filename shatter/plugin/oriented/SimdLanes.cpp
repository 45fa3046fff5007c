#include <shatter/plugin/oriented/SimdLanes.h>

namespace shatter::oriented {

SimdPath fastestSimdPath() {
    static const SimdPath path = simdPathAvailable(SimdPath::Avx2) ? SimdPath::Avx2 : SimdPath::Portable;
    return path;
}

} // namespace shatter::oriented
