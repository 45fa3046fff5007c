#pragma once
// Hints for a loop that frees or overwrites primitives lying all over a large body (timing
// only: a hint never changes a result; see common/Prefetch.h).
#include <shatter/plugin/common/Prefetch.h>
#include <shatter/plugin/geometry/ConvexPolyhedron.h>

#include <memory>
#include <vector>

namespace shatter::geometry {

// The members prefetchPolyhedraAhead reads, at a polyhedron's start (ConvexPolyhedron's first
// four: vertices_, faces_, planes_, globalIds_): three vectors and the face pointer (88 bytes).
inline constexpr size_t kPolyhedronMembers = 3 * sizeof(std::vector<int>) + sizeof(std::shared_ptr<const FaceList>);

// For a loop over primitives[slotAt(k)], k = 0..n-1, that frees or overwrites their blocks:
// called before step k, it asks for the blocks of the one kAhead on (the allocator reads each
// block's header, the 16 bytes before it, in the line of its start 3 times in 4; an overwrite
// writes from the start) and for the members of the one 2 * kAhead on (the vectors' pointers
// the first hints read). A fracture's ~500 removed primitives lie all over a 16k rest, their
// blocks with them: in perf, freeing them (six blocks each) was a miss at every block
// (applyRemainderEdit's free samples 1.0-1.2 % of the event, 0.1-0.3 % with these hints).
template <class SlotAt>
[[gnu::always_inline]] inline void prefetchPolyhedraAhead(const std::vector<ConvexPolyhedron>& primitives,
                                                          const SlotAt& slotAt, size_t n, size_t k) {
    constexpr size_t kAhead = 8;
    if (k + 2 * kAhead < n) prefetchRange(&primitives[size_t(slotAt(k + 2 * kAhead))], kPolyhedronMembers);
    if (k + kAhead >= n) return;
    // One line each, a start, not a range (prefetchRange per block: 0.22 M instructions more in
    // five 16k-shell events).
    const ConvexPolyhedron& p = primitives[size_t(slotAt(k + kAhead))];
    __builtin_prefetch(p.vertices().data());
    __builtin_prefetch(p.planes().data());
    __builtin_prefetch(p.globalIds().data());
    const FaceList& faces = p.faces(); // the shared block, its count just before it
    __builtin_prefetch(&faces);
    __builtin_prefetch(faces.indices().data());
    __builtin_prefetch(faces.starts().data());
}

} // namespace shatter::geometry
