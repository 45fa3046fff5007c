#pragma once
// Asking the memory system for data ahead of its use. Timing only: a prefetch never changes
// a result. Used where the fracture event walks data that lies apart in memory and is mostly
// out of cache (a large body's primitives, tree nodes); each use says what it measured.
#include <cstddef>
#include <cstdint>

namespace shatter {

inline constexpr std::uintptr_t kCacheLine = 64; // bytes, x86-64 and most ARM cores

// Every cache line that [begin, begin + bytes) touches, also when begin is not at a line's
// start (a 48-byte box at offset 88 of an object spans two lines). Integer addresses: no
// pointer is formed outside the object. Inlined by force, as must be any wrapper made of
// hints alone: GCC 12 finds such a function "const" and drops its calls (review53b: at -O2 no
// prefetch was left in the fracture cutting loops).
[[gnu::always_inline]] inline void prefetchRange(const void* begin, size_t bytes) {
    if (bytes == 0) return;
    const std::uintptr_t end = reinterpret_cast<std::uintptr_t>(begin) + bytes;
    for (std::uintptr_t line = reinterpret_cast<std::uintptr_t>(begin) & ~(kCacheLine - 1); line < end; line += kCacheLine)
        __builtin_prefetch(reinterpret_cast<const void*>(line));
}

} // namespace shatter
