#pragma once
// Lanes of doubles as compiler vectors, and the widest instruction set this processor runs.
//
// The solver's hot loops (the batched projection and its rotation fits) are written once on
// DoubleLanes<K>, a GCC/Clang vector of K doubles, and compiled twice: for the portable target
// (x86-64's SSE2: a vector of 4 is two 2-wide instructions) and, in a function marked
// SHATTER_AVX2, for AVX2 (one 4-wide instruction). Which one runs is chosen once at run time
// (fastestSimdPath), so the default build stays portable. AVX2 does not include FMA, so the
// compiler cannot fuse a multiply and an add in either path: every lane does the same IEEE
// operations in the same order and the two paths give the same bits (tested).
#include <shatter/plugin/common/CpuFeatures.h>

#include <cstdint>

namespace shatter::oriented {

enum class SimdPath {
    Portable, // the build's own target (SSE2 on x86-64)
    Avx2,     // 4-wide double lanes; only where the processor has AVX2
};

// Avx2 on an x86 processor that has it, else Portable; decided at the first call.
SimdPath fastestSimdPath();
#if defined(__x86_64__) || defined(__i386__)
#define SHATTER_AVX2 [[gnu::target("avx2")]]
#define SHATTER_HAS_AVX2_PATH 1
#else
#define SHATTER_AVX2
#define SHATTER_HAS_AVX2_PATH 0
#endif

// Whether `path` can run here (Portable always). Inline: the solver checks its path once a
// batch of fits (fitRotations), where a call would cost more than the check.
inline bool simdPathAvailable(SimdPath path) {
    if (path == SimdPath::Portable) return true;
    if (path != SimdPath::Avx2) return false; // not one of the two paths
    return SHATTER_HAS_AVX2_PATH && processorRunsAvx2();
}
// A hot-loop body written on DoubleLanes: inlined into both paths' entry points, which is what
// compiles it for each instruction set (a call would run the portable copy).
#define SHATTER_LANES_INLINE [[gnu::always_inline]] inline

template <int K>
struct LaneTypes;
template <>
struct LaneTypes<1> {
    typedef double Doubles __attribute__((vector_size(8)));
    typedef std::int64_t Mask __attribute__((vector_size(8)));
};
template <>
struct LaneTypes<2> {
    typedef double Doubles __attribute__((vector_size(16)));
    typedef std::int64_t Mask __attribute__((vector_size(16)));
};
template <>
struct LaneTypes<4> {
    typedef double Doubles __attribute__((vector_size(32)));
    typedef std::int64_t Mask __attribute__((vector_size(32)));
};
// K doubles; +, −, ×, ÷ act lane by lane, a scalar operand is broadcast, and a comparison
// gives a LaneMask (all bits set where true).
template <int K>
using DoubleLanes = typename LaneTypes<K>::Doubles;
template <int K>
using LaneMask = typename LaneTypes<K>::Mask;

// These helpers return vectors by value (and take them by reference); they are always inlined,
// never called across the ABI that GCC warns changed for 32-byte vectors.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"
// Where `mask`, a; elsewhere b.
template <int K>
SHATTER_LANES_INLINE DoubleLanes<K> select(const LaneMask<K>& mask, const DoubleLanes<K>& a, const DoubleLanes<K>& b) {
    return mask ? a : b; // a blend where the mask is a constant
}
// |a| lane by lane (the sign bit cleared, as fabs).
template <int K>
SHATTER_LANES_INLINE DoubleLanes<K> abs(const DoubleLanes<K>& a) {
    return DoubleLanes<K>(LaneMask<K>(a) & std::int64_t(0x7fffffffffffffff));
}
// Exactly v in every lane (an added 0 would turn −0 into +0). Written as an initialiser, not a
// loop over the lanes: GCC 12 makes the loop's 4 lanes from a loaded double with two
// instructions (unpack, insert), the initialiser with one (vbroadcastsd from memory on AVX2),
// and the sums take three broadcasts a member.
template <int K>
SHATTER_LANES_INLINE DoubleLanes<K> broadcast(double v) {
    static_assert(K == 1 || K == 4, "DoubleLanes of 1 or 4");
    if constexpr (K == 4) return DoubleLanes<4>{v, v, v, v};
    else return DoubleLanes<1>{v};
}
// rows[i][l] becomes rows[l][i]: four rows of 4 lanes as four columns (8 shuffles on AVX2).
SHATTER_LANES_INLINE void transpose(DoubleLanes<4> (&rows)[4]) {
    const DoubleLanes<4> t0 = __builtin_shufflevector(rows[0], rows[1], 0, 4, 2, 6);
    const DoubleLanes<4> t1 = __builtin_shufflevector(rows[0], rows[1], 1, 5, 3, 7);
    const DoubleLanes<4> t2 = __builtin_shufflevector(rows[2], rows[3], 0, 4, 2, 6);
    const DoubleLanes<4> t3 = __builtin_shufflevector(rows[2], rows[3], 1, 5, 3, 7);
    rows[0] = __builtin_shufflevector(t0, t2, 0, 1, 4, 5);
    rows[1] = __builtin_shufflevector(t1, t3, 0, 1, 4, 5);
    rows[2] = __builtin_shufflevector(t0, t2, 2, 3, 6, 7);
    rows[3] = __builtin_shufflevector(t1, t3, 2, 3, 6, 7);
}
#pragma GCC diagnostic pop

} // namespace shatter::oriented
