#pragma once
// Four doubles operated on lane by lane: GCC's vector extension, one AVX register. Used only
// in the x86-64-v3 and x86-64-v4 copies of the transfers (TransferTargets.h; the v4 copy also
// pairs two of them as a Double8). A grid node is four doubles
// (Grid::Node) and a cubic stencil row is four nodes, so the transfers of the cubic kernel
// work a node, or a row of weights, at a time.
// The helpers are always_inline: they run only inside the x86-64-v3 transfer loops, and a
// vector passed to a non-inlined function would depend on the copy's calling convention.
// GCC warns that a function returning a Double4 would pass it differently with and without
// AVX; these never cross a call (always_inline), so the warning does not apply. It is off for
// the rest of the including file too (not pushed and popped): GCC warns again at each
// inlined call.
#pragma GCC diagnostic ignored "-Wpsabi"

namespace shatter::mpm {

using Double4 = double __attribute__((vector_size(4 * sizeof(double))));

// Loads and stores at any 8-byte boundary. Through this type (not memcpy, which may alias
// anything) the compiler knows that a store changes only doubles, and keeps pointers and
// indices in registers across it.
using UnalignedDouble4 = double __attribute__((vector_size(4 * sizeof(double)), aligned(alignof(double))));

// Clang keeps a vector's own alignment (32 bytes) through `aligned` on a typedef, so there the
// access through UnalignedDouble4 would be a misaligned load (UBSan reported it from the scene
// fuzzer); a memcpy is clang's unaligned vector load and store, the same instructions.
#if defined(__clang__)
[[gnu::always_inline]] inline Double4 load4(const double* p) {
    Double4 v;
    __builtin_memcpy(&v, p, sizeof v);
    return v;
}
[[gnu::always_inline]] inline void store4(double* p, const Double4& v) { __builtin_memcpy(p, &v, sizeof v); }
#else
[[gnu::always_inline]] inline Double4 load4(const double* p) { return *reinterpret_cast<const UnalignedDouble4*>(p); }

[[gnu::always_inline]] inline void store4(double* p, const Double4& v) { *reinterpret_cast<UnalignedDouble4*>(p) = v; }
#endif

// Two Double4s side by side: one AVX-512 register, used only in the x86-64-v4 copies of the
// transfers (TransferTargets.h): two grid nodes, or a Double4 of each of two particles.
using Double8 = double __attribute__((vector_size(8 * sizeof(double))));
using UnalignedDouble8 = double __attribute__((vector_size(8 * sizeof(double)), aligned(alignof(double))));
#if defined(__clang__) // as load4
[[gnu::always_inline]] inline Double8 load8(const double* p) {
    Double8 v;
    __builtin_memcpy(&v, p, sizeof v);
    return v;
}
[[gnu::always_inline]] inline void store8(double* p, const Double8& v) { __builtin_memcpy(p, &v, sizeof v); }
#else
[[gnu::always_inline]] inline Double8 load8(const double* p) { return *reinterpret_cast<const UnalignedDouble8*>(p); }
[[gnu::always_inline]] inline void store8(double* p, const Double8& v) { *reinterpret_cast<UnalignedDouble8*>(p) = v; }
#endif
// (a, b) in one Double8.
[[gnu::always_inline]] inline Double8 join(const Double4& a, const Double4& b) {
    return __builtin_shufflevector(a, b, 0, 1, 2, 3, 4, 5, 6, 7);
}
// The columns of the 4 x 4 matrix with rows a, b, c, d: out[k] = (a[k], b[k], c[k], d[k]).
[[gnu::always_inline]] inline void transpose4(const Double4& a, const Double4& b, const Double4& c, const Double4& d,
                                              Double4 out[4]) {
    const Double4 ab01 = __builtin_shufflevector(a, b, 0, 4, 1, 5), ab23 = __builtin_shufflevector(a, b, 2, 6, 3, 7);
    const Double4 cd01 = __builtin_shufflevector(c, d, 0, 4, 1, 5), cd23 = __builtin_shufflevector(c, d, 2, 6, 3, 7);
    out[0] = __builtin_shufflevector(ab01, cd01, 0, 1, 4, 5);
    out[1] = __builtin_shufflevector(ab01, cd01, 2, 3, 6, 7);
    out[2] = __builtin_shufflevector(ab23, cd23, 0, 1, 4, 5);
    out[3] = __builtin_shufflevector(ab23, cd23, 2, 3, 6, 7);
}

} // namespace shatter::mpm
