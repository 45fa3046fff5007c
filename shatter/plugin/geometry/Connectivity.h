#pragma once
// Which primitives touch or overlap at rest (source 000 §3.1): an AABB-tree broadphase and
// a libccd GJK narrowphase on the primitives grown by half the tolerance each, so that
// two convex solids count as touching when their distance is at most the tolerance.
#include <shatter/plugin/geometry/ConvexPolyhedron.h>

#include <utility>
#include <vector>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace shatter::geometry {

// Whether the id lists a and b have an id in common (pieces that share a vertex id touch;
// fracture's island test). Each of a's ids against all of b's with one branch, four at a time
// (SSE2; by std::find fracture's joining took 0.6 M instructions more of 8.2 M in five events
// of the 16k shell); the last four overlap the others rather than a scalar tail. Inline: fracture calls
// it ~3k times an event of the 16k shell, on lists of ~8 ids. A shared id is found soonest
// when it is early in `a`.
inline bool shareAnId(const std::vector<int>& a, const std::vector<int>& b) {
    const int* const other = b.data();
    const size_t n = b.size();
#if defined(__SSE2__)
    if (n >= 4) {
        auto four = [other](size_t k) { return _mm_loadu_si128(reinterpret_cast<const __m128i*>(other + k)); };
        const __m128i last = four(n - 4);
        for (const int i : a) {
            const __m128i id = _mm_set1_epi32(i);
            __m128i hits = _mm_cmpeq_epi32(id, last);
            for (size_t k = 0; k + 4 < n; k += 4) hits = _mm_or_si128(hits, _mm_cmpeq_epi32(id, four(k)));
            if (_mm_movemask_epi8(hits) != 0) return true;
        }
        return false;
    }
#endif
    for (const int i : a)
        for (size_t k = 0; k < n; ++k)
            if (other[k] == i) return true;
    return false;
}

// Whether a and b are at most `tolerance` apart (0 for overlap or contact). GJK runs on
// a and b each grown by a sphere of radius tolerance/2.
bool withinTolerance(const ConvexPolyhedron& a, const ConvexPolyhedron& b, double tolerance);

// All pairs (a < b) of primitives at most `tolerance` apart, sorted.
std::vector<std::pair<int, int>> touchingPairs(const std::vector<ConvexPolyhedron>& primitives, double tolerance);

// Primitives at most `tolerance` from `probe`, ascending.
std::vector<int> primitivesTouching(const std::vector<ConvexPolyhedron>& primitives, const ConvexPolyhedron& probe,
                                    double tolerance);

// Number of connected components of a graph over nodes 0..nodeCount-1.
int countComponents(int nodeCount, const std::vector<std::pair<int, int>>& edges);

} // namespace shatter::geometry
