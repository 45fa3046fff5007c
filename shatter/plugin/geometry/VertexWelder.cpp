#include <shatter/plugin/geometry/VisualMesh.h>
#include <shatter/plugin/common/Prefetch.h>

#include <algorithm>
#include <stdexcept>
#include <string>

namespace shatter::geometry {

namespace {

[[noreturn]] void layoutMismatch(const std::string& what) {
    throw std::invalid_argument("VertexWelder: " + what + " differ from those the welder was built for");
}

// Room in the per-id lists' heads for `id`. Ids come in any order (ascending in a fragment,
// new ones one by one in a fracture's swaps): grown by an eighth at least, not one call per
// new largest id.
void makeRoomForId(std::vector<int>& firstCarrier, int id) {
    if (size_t(id) >= firstCarrier.size())
        firstCarrier.resize(std::max(size_t(id) + 1, firstCarrier.size() + firstCarrier.size() / 8 + 64), -1);
}

// One carrier's share of its id's average, and the average from the sum of the shares: weld()
// and weldCarriedOnlyBy() both go through these, so that they round alike.
inline void addShare(Eigen::Vector3d& sum, const Eigen::Vector3d& vertex, const Eigen::Vector3d& reference,
                     double inverseCount) {
    sum += (vertex - reference) * inverseCount;
}

inline Eigen::Vector3d averageFrom(const Eigen::Isometry3d& transform, const Eigen::Vector3d& reference,
                                   const Eigen::Vector3d& sum) {
    return transform * (reference + sum);
}

// fillHoles' pass over a break's removed primitives (~500 of the 16k shell's, spread over the
// whole index range) reads their blocks one cache miss after the other (perf: two thirds of
// fillHoles' own time). These hints load what the pass reads kAhead and 2 kAhead removals on
// (values read for a hint only choose what is loaded): fillHoles' perf samples 222 -> 148 (200
// 16k x 64 events, 2 interleaved pairs; kAhead 8 gained less). Hints for recount's lists (the
// head kAhead touched ids on, and its first entry) cost more than they saved (+4 to +30
// samples of fillHoles + recount): the touched ids repeat, so the head is often a hit already.
// Hints alone, so inlined by force (see Prefetch.h).
constexpr size_t kAhead = 16;

// For removed[k]'s block: its start and size, then its ids and owners.
[[gnu::always_inline]] inline void prefetchBlocks(const std::vector<int>& removed, size_t k, const int* blockStart,
                                                  const int* blockSize, const int* flatIds, const int* owner) {
    if (k + 2 * kAhead < removed.size()) {
        __builtin_prefetch(blockStart + removed[k + 2 * kAhead]);
        __builtin_prefetch(blockSize + removed[k + 2 * kAhead]);
    }
    if (k + kAhead < removed.size()) { // a block may cross a line: all of it
        const int r = removed[k + kAhead];
        prefetchRange(flatIds + blockStart[r], size_t(blockSize[r]) * sizeof(int));
        prefetchRange(owner + blockStart[r], size_t(blockSize[r]) * sizeof(int));
    }
}

} // namespace

VertexWelder::VertexWelder(const std::vector<ConvexPolyhedron>& primitives, int visualVertexCount) {
    const int n = std::max(visualVertexCount, 0);
    size_t flat = 0;
    int largestId = -1;
    for (const auto& p : primitives) {
        flat += p.globalIds().size();
        for (const int id : p.globalIds()) largestId = std::max(largestId, id);
    }
    blockStart_.resize(primitives.size());
    blockSize_.resize(primitives.size());
    // Room for an eighth more entries and visual ids, so that fillHoles can append a
    // fracture's pieces and new visual ids without moving the arrays (a move of a 16k-primitive
    // rest's ~130k entries cost 1.5 M instructions; room never written costs no memory).
    const size_t spare = flat / 8, spareIds = size_t(n) / 8;
    flatIds_.reserve(flat + spare);
    flatOwner_.reserve(flat + spare);
    nextCarrier_.reserve(flat + spare);
    // Inner ids too: about one per visual id (extrusion). And room for makeRoomForId's first
    // growth by an eighth: without it, the 16k shell rest's ~32k heads moved at every break
    // (0.65 M instructions of five breaks).
    const size_t heads = size_t(std::max(n, largestId + 1));
    firstCarrier_.reserve(std::max(2 * (size_t(n) + spareIds), heads + heads / 4 + 64));
    firstCarrier_.assign(heads, -1); // inner ids (>= n) have lists too
    inverseCount_.reserve(size_t(n) + spareIds);
    referencePrimitive_.reserve(size_t(n) + spareIds);
    referenceVertex_.reserve(size_t(n) + spareIds);
    inverseCount_.assign(n, 0.0);
    referencePrimitive_.assign(n, -1);
    referenceVertex_.assign(n, 0);
    writeBlocks(primitives, flat);
    for (double& c : inverseCount_) c = c > 0.0 ? 1.0 / c : 0.0;
    for (int id = 0; id < n; ++id)
        if (referencePrimitive_[size_t(id)] < 0) uncarried_.push_back(id);
}

void VertexWelder::relistUncarried(const std::vector<int>& recounted, const std::vector<char>& recountedMark) {
    const int n = int(referencePrimitive_.size());
    size_t kept = 0;
    for (const int id : uncarried_)
        if (id < n && !recountedMark[size_t(id)]) uncarried_[kept++] = id;
    uncarried_.resize(kept);
    for (const int id : recounted)
        if (referencePrimitive_[size_t(id)] < 0) uncarried_.push_back(id);
}

void VertexWelder::writeBlocks(const std::vector<ConvexPolyhedron>& primitives, size_t flat) {
    // One forward pass that writes each primitive's ids into its block of flat entries (each
    // put at the head of its id's list) and counts them, into arrays sized once. Through
    // appendBlock (three push_backs and a room check an entry) the fragments' welders of five
    // 64-cell breaks of the 16k shell cost 4.11 M instructions, 3.26 M so.
    flatIds_.resize(flat);
    flatOwner_.resize(flat);
    nextCarrier_.resize(flat);
    int* const flatIds = flatIds_.data();
    int* const owner = flatOwner_.data();
    int* const next = nextCarrier_.data();
    int* const first = firstCarrier_.data(); // sized for the largest id by the constructor
    double* const count = inverseCount_.data();
    int* const referencePrimitive = referencePrimitive_.data();
    int* const referenceVertex = referenceVertex_.data();
    const int n = int(inverseCount_.size());
    int entry = 0;
    for (int p = 0; p < int(primitives.size()); ++p) {
        const std::vector<int>& ids = primitives[size_t(p)].globalIds();
        blockStart_[size_t(p)] = entry;
        blockSize_[size_t(p)] = int(ids.size());
        for (int k = 0; k < int(ids.size()); ++k, ++entry) {
            const int id = ids[size_t(k)];
            flatIds[entry] = id;
            owner[entry] = p;
            next[entry] = -1;
            if (id < 0) continue;
            next[entry] = first[id];
            first[id] = entry;
            if (id >= n) continue;
            count[id] += 1.0;
            if (referencePrimitive[id] < 0) { // the reference is the first vertex carrying the id
                referencePrimitive[id] = p;
                referenceVertex[id] = k;
            }
        }
    }
}

void VertexWelder::appendBlock(int p, const std::vector<int>& ids) {
    blockStart_[size_t(p)] = int(flatIds_.size());
    blockSize_[size_t(p)] = int(ids.size());
    for (const int id : ids) {
        const int entry = int(flatIds_.size());
        flatIds_.push_back(id);
        flatOwner_.push_back(p);
        nextCarrier_.push_back(-1);
        if (id < 0) continue;
        makeRoomForId(firstCarrier_, id);
        nextCarrier_.back() = firstCarrier_[size_t(id)];
        firstCarrier_[size_t(id)] = entry;
    }
}

template <class VertexAt>
void VertexWelder::average(const VertexAt& vertex, const Eigen::Isometry3d& transform,
                           std::vector<Eigen::Vector3d>& positions) const {
    const int n = int(inverseCount_.size());
    positions.resize(n);
    for (int id = 0; id < n; ++id)
        if (referencePrimitive_[id] >= 0) positions[id].setZero();
    // Offsets from the reference vertex: exactly zero for coincident vertices, and small
    // numbers (no cancellation) for a mesh far from the origin.
    const int primitiveCount = int(blockStart_.size());
    for (int p = 0; p < primitiveCount; ++p) {
        const int start = blockStart_[size_t(p)];
        for (int k = 0; k < blockSize_[size_t(p)]; ++k) {
            const int id = flatIds_[size_t(start + k)];
            if (id < 0 || id >= n) continue;
            const Eigen::Vector3d& ref = vertex(referencePrimitive_[id], referenceVertex_[id]);
            addShare(positions[id], vertex(p, k), ref, inverseCount_[id]);
        }
    }
    for (int id = 0; id < n; ++id)
        if (referencePrimitive_[id] >= 0)
            positions[id] = averageFrom(transform, vertex(referencePrimitive_[id], referenceVertex_[id]), positions[id]);
}

void VertexWelder::checkAscending(const std::vector<int>& indices, const char* what) const {
    const int count = int(blockSize_.size());
    for (size_t k = 0; k < indices.size(); ++k)
        if (indices[k] < 0 || indices[k] >= count || (k > 0 && indices[k] <= indices[k - 1]))
            throw std::invalid_argument(std::string("VertexWelder::") + what + ": primitives must be ascending indices below " +
                                        std::to_string(count) + " (" + std::to_string(indices[k]) + " is not)");
}

void VertexWelder::weldCarriedOnlyBy(const std::vector<ConvexPolyhedron>& primitives, const std::vector<int>& only,
                                     const Eigen::Isometry3d& transform, std::vector<Eigen::Vector3d>& positions) const {
    checkAscending(only, "weldCarriedOnlyBy");
    if (primitives.size() != blockSize_.size()) layoutMismatch("primitive count");
    for (const int p : only)
        if (int(primitives[size_t(p)].vertices().size()) != blockSize_[size_t(p)]) layoutMismatch("vertex counts");
    const int n = int(inverseCount_.size());
    if (positions.size() < size_t(n)) positions.resize(size_t(n));
    // Per visual id: 1 once seen among `only`'s ids, 2 when no other primitive carries it.
    std::vector<char> state(size_t(n), 0);
    auto other = [&](int id) {
        for (int e = firstCarrier_[size_t(id)]; e >= 0; e = nextCarrier_[size_t(e)])
            if (flatOwner_[size_t(e)] >= 0 && !std::binary_search(only.begin(), only.end(), flatOwner_[size_t(e)]))
                return true;
        return false;
    };
    for (const int p : only)
        for (int e = blockStart_[size_t(p)]; e < blockStart_[size_t(p)] + blockSize_[size_t(p)]; ++e) {
            const int id = flatIds_[size_t(e)];
            if (id < 0 || id >= n || state[size_t(id)] != 0) continue;
            state[size_t(id)] = other(id) ? 1 : 2;
            if (state[size_t(id)] == 2) positions[size_t(id)].setZero();
        }
    // All of an id's carriers are in `only`, so `only` in order gives its shares in weld()'s order.
    auto vertex = [&](int p, int k) -> const Eigen::Vector3d& { return primitives[size_t(p)].vertices()[size_t(k)]; };
    for (const int p : only)
        for (int k = 0; k < blockSize_[size_t(p)]; ++k) {
            const int id = flatIds_[size_t(blockStart_[size_t(p)] + k)];
            if (id < 0 || id >= n || state[size_t(id)] != 2) continue;
            addShare(positions[size_t(id)], vertex(p, k), vertex(referencePrimitive_[id], referenceVertex_[id]),
                     inverseCount_[size_t(id)]);
        }
    for (const int p : only)
        for (int e = blockStart_[size_t(p)]; e < blockStart_[size_t(p)] + blockSize_[size_t(p)]; ++e) {
            const int id = flatIds_[size_t(e)];
            if (id < 0 || id >= n || state[size_t(id)] != 2) continue;
            state[size_t(id)] = 3; // finished once
            positions[size_t(id)] =
                averageFrom(transform, vertex(referencePrimitive_[id], referenceVertex_[id]), positions[size_t(id)]);
        }
}

void VertexWelder::removePrimitives(const std::vector<ConvexPolyhedron>& primitives, const std::vector<int>& removed) {
    checkAscending(removed, "removePrimitives");
    const int oldCount = int(blockSize_.size());
    if (primitives.size() + removed.size() != size_t(oldCount))
        throw std::invalid_argument("VertexWelder::removePrimitives: " + std::to_string(primitives.size()) +
                                    " primitives given, the removal leaves " +
                                    std::to_string(oldCount - int(removed.size())));
    if (removed.empty()) return;
    const int n = int(inverseCount_.size());
    // The removed primitives' entries die; their ids' counts and reference vertices change.
    std::vector<int> touched;
    for (const int r : removed) {
        for (int e = blockStart_[size_t(r)]; e < blockStart_[size_t(r)] + blockSize_[size_t(r)]; ++e) {
            touched.push_back(flatIds_[size_t(e)]);
            flatOwner_[size_t(e)] = -1;
        }
        deadEntries_ += blockSize_[size_t(r)];
    }
    // The survivors from the first removed one on close up (to: old index -> new, -1 removed).
    // Through plain pointers: the vectors' own members would be reloaded after every store.
    const int first = removed.front();
    std::vector<int> to(size_t(oldCount - first));
    int* newIndex = to.data(); // newIndex[p - first]: p's new index
    int* start = blockStart_.data();
    int* size = blockSize_.data();
    int* owner = flatOwner_.data();
    int kept = first;
    size_t next = 0;
    for (int p = first; p < oldCount; ++p) {
        if (next < removed.size() && removed[next] == p) {
            ++next;
            newIndex[p - first] = -1;
            continue;
        }
        newIndex[p - first] = kept;
        const int s = start[p], c = size[p];
        start[kept] = s;
        size[kept] = c;
        for (int e = s; e < s + c; ++e) owner[e] = kept;
        ++kept;
    }
    blockStart_.resize(size_t(kept));
    blockSize_.resize(size_t(kept));
    // Closing up keeps the order, so an id no removed primitive carried keeps its reference
    // vertex, renumbered; the others are counted again from their lists.
    for (int& p : referencePrimitive_)
        if (p >= first) p = newIndex[p - first];
    std::sort(touched.begin(), touched.end());
    touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
    std::vector<int> recounted;
    std::vector<char> recountedMark(size_t(n), 0);
    for (const int id : touched)
        if (id >= 0 && id < n) {
            recount(id);
            recounted.push_back(id);
            recountedMark[size_t(id)] = 1;
        }
    relistUncarried(recounted, recountedMark);
    // Dead entries outnumber the live ones: rebuilt (the same welder, compact again).
    if (2 * deadEntries_ > int(flatIds_.size())) *this = VertexWelder(primitives, n);
}

std::vector<int> VertexWelder::primitivesCarrying(const std::vector<int>& ids) const {
    // Marks per primitive, read in order: a fracture's swapped ids have ~16k carrying
    // vertices on ~1k primitives, which sorting cost 0.4 M instructions.
    std::vector<char> carries(blockStart_.size(), 0);
    for (const int id : ids) {
        if (id < 0 || size_t(id) >= firstCarrier_.size()) continue;
        for (int e = firstCarrier_[size_t(id)]; e >= 0; e = nextCarrier_[size_t(e)])
            if (flatOwner_[size_t(e)] >= 0) carries[size_t(flatOwner_[size_t(e)])] = 1;
    }
    std::vector<int> found;
    for (size_t p = 0; p < carries.size(); ++p)
        if (carries[p]) found.push_back(int(p));
    return found;
}

void VertexWelder::recount(int id) {
    // The fresh welder's count (exact in a double) and its first carrier in primitive order,
    // then vertex order; dead entries met on the way leave the list. A primitive's entries
    // are one block, so among its entries vertex order is entry order: the block's start is
    // read once at the end, not at every entry (a dependent load, often a miss).
    int count = 0, firstPrimitive = -1, firstEntry = 0;
    int* link = &firstCarrier_[size_t(id)];
    while (*link >= 0) {
        const int e = *link;
        const int p = flatOwner_[size_t(e)];
        if (p < 0) {
            *link = nextCarrier_[size_t(e)];
            continue;
        }
        ++count;
        if (firstPrimitive < 0 || p < firstPrimitive || (p == firstPrimitive && e < firstEntry)) {
            firstPrimitive = p;
            firstEntry = e;
        }
        link = &nextCarrier_[size_t(e)];
    }
    inverseCount_[size_t(id)] = count > 0 ? 1.0 / double(count) : 0.0;
    referencePrimitive_[size_t(id)] = firstPrimitive;
    referenceVertex_[size_t(id)] = firstPrimitive >= 0 ? firstEntry - blockStart_[size_t(firstPrimitive)] : 0;
}

void VertexWelder::fillHoles(const std::vector<ConvexPolyhedron>& primitives, const std::vector<int>& removed,
                             const HoleFilling& slots, const std::vector<std::pair<int, int>>& idSwaps,
                             int visualVertexCount) {
    if (primitives.size() != size_t(slots.size))
        throw std::invalid_argument("VertexWelder::fillHoles: " + std::to_string(primitives.size()) +
                                    " primitives given, the edit leaves " + std::to_string(slots.size));
    const int n = std::max(visualVertexCount, 0);
    // Ids whose count or first carrier may change: those of the removed, moved and added
    // primitives, both sides of every swap, and the ids that become visual.
    std::vector<int> touched;
    size_t touching = 2 * idSwaps.size() + size_t(std::max(n - int(inverseCount_.size()), 0));
    for (const int r : removed) touching += size_t(blockSize_[size_t(r)]);
    for (const auto& move : slots.moves) touching += size_t(blockSize_[size_t(move.first)]);
    for (const int p : slots.addedAt) touching += primitives[size_t(p)].globalIds().size();
    touched.reserve(touching); // grown by doubling, its copies cost 0.2 M instructions in a 16k x 64 break
    auto touchBlock = [&](int p) {
        for (int e = blockStart_[size_t(p)]; e < blockStart_[size_t(p)] + blockSize_[size_t(p)]; ++e)
            touched.push_back(flatIds_[size_t(e)]);
    };
    for (size_t k = 0; k < removed.size(); ++k) {
        prefetchBlocks(removed, k, blockStart_.data(), blockSize_.data(), flatIds_.data(), flatOwner_.data());
        const int r = removed[k];
        touchBlock(r);
        for (int e = blockStart_[size_t(r)]; e < blockStart_[size_t(r)] + blockSize_[size_t(r)]; ++e)
            flatOwner_[size_t(e)] = -1;
        deadEntries_ += blockSize_[size_t(r)];
    }
    // A swap exchanges the two ids' lists (the kept carriers of one now carry the other).
    for (const auto& [a, b] : idSwaps) {
        makeRoomForId(firstCarrier_, std::max(a, b));
        std::swap(firstCarrier_[size_t(a)], firstCarrier_[size_t(b)]);
        for (int e = firstCarrier_[size_t(a)]; e >= 0; e = nextCarrier_[size_t(e)]) flatIds_[size_t(e)] = a;
        for (int e = firstCarrier_[size_t(b)]; e >= 0; e = nextCarrier_[size_t(e)]) flatIds_[size_t(e)] = b;
        touched.push_back(a);
        touched.push_back(b);
    }
    const size_t room = std::max(blockStart_.size(), size_t(slots.size));
    blockStart_.resize(room);
    blockSize_.resize(room);
    for (const auto& [from, to] : slots.moves) {
        blockStart_[size_t(to)] = blockStart_[size_t(from)];
        blockSize_[size_t(to)] = blockSize_[size_t(from)];
        for (int e = blockStart_[size_t(to)]; e < blockStart_[size_t(to)] + blockSize_[size_t(to)]; ++e)
            flatOwner_[size_t(e)] = to;
        touchBlock(to);
    }
    for (const int p : slots.addedAt) {
        appendBlock(p, primitives[size_t(p)].globalIds());
        touchBlock(p);
    }
    blockStart_.resize(size_t(slots.size));
    blockSize_.resize(size_t(slots.size));

    const int oldN = int(inverseCount_.size());
    inverseCount_.resize(size_t(n), 0.0);
    referencePrimitive_.resize(size_t(n), -1);
    referenceVertex_.resize(size_t(n), 0);
    if (firstCarrier_.size() < size_t(n)) firstCarrier_.resize(size_t(n), -1);
    for (int id = oldN; id < n; ++id) touched.push_back(id);
    std::vector<char> done(size_t(n), 0);
    std::vector<int> recounted;
    recounted.reserve(touched.size());
    for (const int id : touched)
        if (id >= 0 && id < n && !done[size_t(id)]) {
            done[size_t(id)] = 1;
            recount(id);
            recounted.push_back(id);
        }
    relistUncarried(recounted, done);
    // Dead entries outnumber the live ones: rebuilt (the same welder, compact again).
    if (2 * deadEntries_ > int(flatIds_.size())) *this = VertexWelder(primitives, n);
}


void VertexWelder::weld(const std::vector<ConvexPolyhedron>& primitives, const Eigen::Isometry3d& transform,
                        std::vector<Eigen::Vector3d>& positions) const {
    if (primitives.size() != blockSize_.size()) layoutMismatch("primitive count");
    for (size_t p = 0; p < primitives.size(); ++p)
        if (int(primitives[p].vertices().size()) != blockSize_[p]) layoutMismatch("vertex counts");
    average([&](int p, int k) -> const Eigen::Vector3d& { return primitives[p].vertices()[k]; }, transform, positions);
}

void VertexWelder::weld(std::span<const Eigen::Vector3d> flatVertices, const Eigen::Isometry3d& transform,
                        std::vector<Eigen::Vector3d>& positions) const {
    // The caller's array is compact, primitive after primitive; the welder's own blocks may
    // have moved and left dead entries (fillHoles), so each primitive's offset is counted here.
    std::vector<int> offset(blockSize_.size());
    size_t total = 0;
    for (size_t p = 0; p < blockSize_.size(); ++p) {
        offset[p] = int(total);
        total += size_t(blockSize_[p]);
    }
    if (flatVertices.size() != total) layoutMismatch("vertex counts");
    average([&](int p, int k) -> const Eigen::Vector3d& { return flatVertices[size_t(offset[size_t(p)] + k)]; }, transform,
            positions);
}

} // namespace shatter::geometry
