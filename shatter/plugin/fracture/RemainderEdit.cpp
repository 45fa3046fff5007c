#include <shatter/plugin/fracture/RemainderEdit.h>

#include <shatter/plugin/common/InputError.h>
#include <shatter/plugin/geometry/HoleFilling.h>
#include <shatter/plugin/geometry/PolyhedronPrefetch.h>

#include <algorithm>
#include <cstring>
#include <string>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace shatter::fracture {

geometry::MassProperties withoutPart(const geometry::MassProperties& whole, const geometry::MassProperties& part) {
    geometry::MassProperties rest;
    rest.volume = whole.volume - part.volume;
    rest.mass = whole.mass - part.mass;
    if (rest.mass <= 0.0) return rest;
    rest.centerOfMass = (whole.mass * whole.centerOfMass - part.mass * part.centerOfMass) / rest.mass;
    // Inertia about the whole's centre is the sum of both parts' (parallel axes); take the
    // part's out and move what is left to the rest's own centre.
    auto shift = [](double m, const Eigen::Vector3d& d) {
        return Eigen::Matrix3d(m * (d.squaredNorm() * Eigen::Matrix3d::Identity() - d * d.transpose()));
    };
    const Eigen::Matrix3d restAboutWhole =
        whole.inertia - part.inertia - shift(part.mass, part.centerOfMass - whole.centerOfMass);
    rest.inertia = restAboutWhole - shift(rest.mass, rest.centerOfMass - whole.centerOfMass);
    return rest;
}

void applyFaceEdit(geometry::VisualMesh& visual, const RemainderEdit& edit) {
    // The gained faces take the dropped ones' places and the last faces fill the holes left
    // (geometry::fillHoles), where closing up in order moved every face after the first
    // dropped one (two visual meshes of ~16k faces per break).
    const int before = int(visual.faces.size());
    const geometry::HoleFilling slots = geometry::fillHoles(before, edit.droppedFaces, int(edit.faces.size()));
    // "Empty when the mesh has no crack face": a mesh without any gains them only from the
    // edit, so only the edit's flags are searched (not bit by bit over the whole mesh).
    const bool hadCracks = !visual.crackFace.empty();
    const bool cracks = hadCracks || std::find(edit.crack.begin(), edit.crack.end(), true) != edit.crack.end();
    if (hadCracks) visual.crackFace.resize(size_t(before), false);
    for (const auto& [from, hole] : slots.moves) {
        visual.faces[size_t(hole)] = std::move(visual.faces[size_t(from)]);
        if (hadCracks) visual.crackFace[size_t(hole)] = visual.crackFace[size_t(from)];
    }
    const size_t room = size_t(std::max(before, slots.size));
    visual.faces.resize(room);
    if (cracks) visual.crackFace.resize(room, false);
    for (size_t j = 0; j < edit.faces.size(); ++j) {
        const size_t at = size_t(slots.addedAt[j]);
        visual.faces[at] = edit.faces[j];
        if (cracks) visual.crackFace[at] = j < edit.crack.size() && edit.crack[j];
    }
    visual.faces.resize(size_t(slots.size));
    if (cracks) visual.crackFace.resize(size_t(slots.size));
}

namespace {

// Each kept primitive's source face (>= 0) becomes faceIndex[source]; removed ones (primitiveTo
// < 0) keep theirs. Through plain pointers: a store through the body's sourceFace may alias the
// vectors' members, which were then reloaded at every primitive.
void renumberSourceFaces(int* sourceFace, const int* primitiveTo, const int* faceIndex, int count) {
    for (int i = 0; i < count; ++i) {
        const int source = sourceFace[i];
        if (primitiveTo[i] >= 0 && source >= 0) sourceFace[i] = faceIndex[source];
    }
}

// The connections not listed as touched, renumbered where they must be, with a check that
// touchedConnections listed every connection with a removed end: one it missed would keep a
// stale index (an end below the rest's new size, now another primitive's place) or become -1.
// The check reads `to` at both ends of every connection, +0.34 M instructions of a 48.8 M
// event (16k primitives, 63k connections); the cheaper tests tried miss most such ends (a
// break's ~540 removed primitives lie in ~120 runs all over the index range, all below the new
// size, so neither the new size nor the gaps between removed runs set most connections apart).
class KeptConnections {
public:
    // `to`: every primitive's index after the edit (-1: removed), `size`: the rest's primitive
    // count, `body`: its name for an error.
    KeptConnections(const std::vector<int>& to, int size, const std::string& body)
        : to_(to.data()), size_(size), body_(body) {}

    // The connections of [c, c + n), the first being the body's connection `firstIndex`. Four
    // at a time with SSE2, then one: one test in lanes for all four (ends in order, below the
    // new size: kept in place) and one sign test of their ends' `to` or-ed together; in a
    // 16k-primitive rest ~1 connection in 100 must be renumbered. (Eight at a time with AVX2
    // gathers took 4.2 → 1.3 M instructions of five 16k events but no measurable time: removed.)
    // Without Check (an edit whose list was found from every connection,
    // TouchedList::FromEveryConnection) only the lane test: the ends' look-ups were
    // ~1.8 M of the 3.5 M instructions of five 16k events. A connection renumbered is still checked.
    template <bool Check>
    void renumberRun(std::pair<int, int>* c, size_t n, size_t firstIndex) {
        static_assert(sizeof(std::pair<int, int>) == 2 * sizeof(int));
        size_t i = 0;
#if defined(__SSE2__)
        for (; i + 4 <= n; i += 4) {
            const __m128 lo = _mm_castsi128_ps(_mm_loadu_si128(reinterpret_cast<const __m128i*>(c + i)));
            const __m128 hi = _mm_castsi128_ps(_mm_loadu_si128(reinterpret_cast<const __m128i*>(c + i + 2)));
            const __m128i first = _mm_castps_si128(_mm_shuffle_ps(lo, hi, _MM_SHUFFLE(2, 0, 2, 0)));
            const __m128i second = _mm_castps_si128(_mm_shuffle_ps(lo, hi, _MM_SHUFFLE(3, 1, 3, 1)));
            const __m128i stays = _mm_and_si128(_mm_cmplt_epi32(first, second), _mm_cmplt_epi32(second, sizes_));
            const bool inPlace = _mm_movemask_ps(_mm_castsi128_ps(stays)) == 0xF;
            if constexpr (Check) {
                const int ends = (to_[c[i].first] | to_[c[i].second] | to_[c[i + 1].first] | to_[c[i + 1].second]) |
                                 (to_[c[i + 2].first] | to_[c[i + 2].second] | to_[c[i + 3].first] | to_[c[i + 3].second]);
                if (inPlace && ends >= 0) continue;
            } else if (inPlace) {
                continue;
            }
            renumberFour(c + i, firstIndex + i);
        }
#endif
        for (; i < n; ++i) {
            const bool stays = c[i].first < c[i].second && c[i].second < size_;
            if (!stays || (Check && (to_[c[i].first] | to_[c[i].second]) < 0)) renumber(c[i], firstIndex + i);
        }
    }

private:
    // Out of line (~1 block in 25): inlined, its counters took registers from the loop of
    // renumberRun, which then stepped five pointers a block (~0.35 M of five 16k events).
    [[gnu::noinline]] void renumberFour(std::pair<int, int>* c, size_t firstIndex) const {
        for (size_t k = 0; k < 4; ++k) renumber(c[k], firstIndex + k);
    }
    // The connection's ends after the edit; throws when one was removed.
    void renumber(std::pair<int, int>& e, size_t index) const {
        const int a = to_[size_t(e.first)], b = to_[size_t(e.second)];
        if (a < 0 || b < 0) missing(e, index);
        e = std::minmax(a, b);
    }

    [[noreturn]] void missing(const std::pair<int, int>& e, size_t index) const {
        const int lost = to_[size_t(e.first)] < 0 ? e.first : e.second;
        throw InputError("body '" + body_ + "': the rest edit loses primitive " + std::to_string(lost) +
                         " but its touchedConnections miss connection " + std::to_string(index) + " (" +
                         std::to_string(e.first) + ", " + std::to_string(e.second) + ")");
    }

    const int* to_;
    int size_;
    const std::string& body_;
#if defined(__SSE2__)
    __m128i sizes_ = _mm_set1_epi32(size_);
#endif
};

// The connections of two kept primitives, renumbered by `to` (-1: removed), in their order,
// in a new list: the body is not touched, so an edit refused here leaves it whole. Only the
// `touched` ones (ascending indices) may have a removed end (checked, see KeptConnections):
// between them each run is copied whole in one block and renumbered only where it must be (a
// 16k-primitive rest has ~63k connections).
// `kept`: storage to build the list in (its content is dropped; when it is as long as the list
// already, as VisualBody keeps it, it is not zeroed first), with room for `gained` more.
// `complete`: the list was found from every connection (TouchedList::FromEveryConnection),
// so the ends of those kept in place are not looked up.
void keptConnections(const geometry::PhysicalMesh& body, const std::vector<int>& touched, bool complete,
                     const std::vector<int>& to, int size, size_t gained, std::vector<std::pair<int, int>>& kept) {
    const std::vector<std::pair<int, int>>& connections = body.connections;
    kept.reserve(connections.size() + gained); // the gained ones are appended without a reallocation
    kept.resize(connections.size());
    const std::pair<int, int>* c = connections.data();
    std::pair<int, int>* out = kept.data();
    KeptConnections check(to, size, body.name);
    size_t into = 0, from = 0;
    auto keepRun = [&](size_t end) { // connections [from, end): both ends kept
        if (end == from) return;
        // One block copy (std::pair is not trivially copyable, so std::copy would go pair by
        // pair; so did an insert of the run, measured: +0.8 M in five 16k events).
        std::memcpy(static_cast<void*>(out + into), c + from, (end - from) * sizeof(*c));
        if (complete)
            check.renumberRun<false>(out + into, end - from, from);
        else
            check.renumberRun<true>(out + into, end - from, from);
        into += end - from;
    };
    for (const int t : touched) {
        if (size_t(t) < from || size_t(t) >= connections.size())
            throw InputError("body '" + body.name + "': the rest edit's touchedConnections are not ascending indices of its " +
                             std::to_string(connections.size()) + " connections (" + std::to_string(t) + ")");
        keepRun(size_t(t));
        const auto [a, b] = c[t];
        if (to[size_t(a)] >= 0 && to[size_t(b)] >= 0) out[into++] = std::minmax(to[size_t(a)], to[size_t(b)]);
        from = size_t(t) + 1;
    }
    keepRun(connections.size());
    kept.resize(into);
}

// The swapped ids' entries of a swap table from id `low` up, each the other id of its swap or
// -1 (RemainderScratch::swapTable's state between edits); writes them on construction and
// puts them back to -1 however the edit ends. Only these entries are written, not the whole
// table (its fill at every break was 0.4 M instructions of five 16k-shell events).
class SwapTableEntries {
public:
    SwapTableEntries(std::vector<int>& table, const RemainderEdit& edit, int low) : table_(table), edit_(edit), low_(low) {
        if (table.size() < size_t(edit.globalIdCount - low)) table.resize(size_t(edit.globalIdCount - low), -1);
        for (const auto& [a, b] : edit.idSwaps) {
            table[size_t(a - low)] = b;
            table[size_t(b - low)] = a;
        }
    }
    ~SwapTableEntries() {
        for (const auto& [a, b] : edit_.idSwaps) table_[size_t(a - low_)] = table_[size_t(b - low_)] = -1;
    }
    SwapTableEntries(const SwapTableEntries&) = delete;
    SwapTableEntries& operator=(const SwapTableEntries&) = delete;

private:
    std::vector<int>& table_;
    const RemainderEdit& edit_;
    int low_;
};

// Refuses swapped ids outside the edit's ids before anything is written: the swap table a body
// keeps between breaks (RemainderScratch) is indexed by them.
void checkIdSwaps(const geometry::PhysicalMesh& body, const RemainderEdit& edit) {
    for (const auto& [a, b] : edit.idSwaps)
        if (std::min(a, b) < 0 || std::max(a, b) >= edit.globalIdCount)
            throw InputError("body '" + body.name + "': remainder edit swaps ids " + std::to_string(a) + " and " +
                             std::to_string(b) + ", outside its " + std::to_string(edit.globalIdCount) + " ids");
}

// Exchanges the ids of edit.idSwaps in the kept primitives (`to` >= 0): those listed in
// `swapCarriers`, or every one when it is null. Only primitives carrying one are copied.
// `swapTable`: -1 everywhere, and so left (SwapTableEntries).
void swapCarriedIds(geometry::PhysicalMesh& body, const RemainderEdit& edit, const std::vector<int>& to,
                    const std::vector<int>* swapCarriers, std::vector<int>& swapTable) {
    if (edit.idSwaps.empty()) return;
    const int before = int(to.size());
    // Table from the lowest swapped id up: swaps are of ids past the visual vertices, so
    // the table is a break's new ids, not the body's.
    int low = edit.globalIdCount;
    for (const auto& [a, b] : edit.idSwaps) low = std::min({low, a, b});
    const SwapTableEntries entries(swapTable, edit, low);
    auto swapTo = [&](int id) { return id < low ? -1 : swapTable[size_t(id - low)]; };
    std::vector<int> swapped; // one scratch for every carrier, written back in place
    auto swapIds = [&](int i) {
        if (to[size_t(i)] < 0) return;
        auto& p = body.primitives[size_t(i)];
        const auto& ids = p.globalIds();
        // Ids before the first swapped one stay: they are not looked at again (a second pass
        // over every carrier's ids was 0.3 M of five 16k events).
        const auto first = std::find_if(ids.begin(), ids.end(), [&](int id) { return swapTo(id) >= 0; });
        if (first == ids.end()) return;
        swapped.assign(ids.begin(), ids.end());
        for (auto id = swapped.begin() + (first - ids.begin()); id != swapped.end(); ++id)
            if (const int other = swapTo(*id); other >= 0) *id = other;
        p.overwriteGlobalIds(swapped);
    };
    if (swapCarriers)
        for (int i : *swapCarriers) swapIds(i);
    else
        for (int i = 0; i < before; ++i) swapIds(i);
}

// Appends the edit's gained connections, whose ends count the kept primitives in order and
// then the added ones, at the places `to` and `addedAt` give them. `finalTo`: storage for
// the map (content replaced).
void appendGainedConnections(geometry::PhysicalMesh& body, const RemainderEdit& edit, const std::vector<int>& to,
                             const std::vector<int>& addedAt, std::vector<int>& finalTo) {
    // Sized once and written through a pointer (push_back kept the end in memory, ~5
    // instructions more a primitive).
    finalTo.resize(to.size() + addedAt.size()); // room for all, cut to what is written
    {
        int* out = finalTo.data();
        for (int t : to)
            if (t >= 0) *out++ = t;
        out = std::copy(addedAt.begin(), addedAt.end(), out);
        finalTo.resize(size_t(out - finalTo.data()));
    }
    for (const auto& [a, b] : edit.connections)
        body.connections.push_back(std::minmax(finalTo[size_t(a)], finalTo[size_t(b)]));
}

// applyRemainderEdit up to placing the `added` pieces, which `place(j, slot)` puts into
// body.primitives[slot] (sized for them). `swapCarriers`: ascending primitives whose ids may
// change, or null to look at every kept primitive's ids. `scratch`: the storage to work in
// (RemainderScratch).
template <class Place>
void applyEdit(geometry::PhysicalMesh& body, const RemainderEdit& edit, int added, const std::vector<int>* swapCarriers,
               RemainderScratch& scratch, TouchedList touched, const Place& place) {
    const int before = int(body.primitives.size());
    const geometry::HoleFilling slots = geometry::fillHoles(before, edit.removed, added);
    std::vector<int>& to = scratch.to;
    slots.newIndex(before, edit.removed, to);
    // First, before any write: this is where an inconsistent edit is refused.
    keptConnections(body, edit.touchedConnections, touched == TouchedList::FromEveryConnection, to, slots.size,
                    edit.connections.size(), scratch.connections);
    checkIdSwaps(body, edit);
    for (int i : edit.lostSourceFace) body.sourceFace[size_t(i)] = -1;
    // Where each face goes (-1: dropped; applyFaceEdit's places); source faces follow their face.
    const int faces = int(body.visual.faces.size());
    geometry::fillHoles(faces, edit.droppedFaces, int(edit.faces.size())).newIndex(faces, edit.droppedFaces, scratch.faceTo);
    renumberSourceFaces(body.sourceFace.data(), to.data(), scratch.faceTo.data(), before);

    swapCarriedIds(body, edit, to, swapCarriers, scratch.swapTable);

    // The pieces take the holes; the last survivors fill those left over. Each frees a removed
    // primitive's blocks: hinted ahead (geometry::prefetchPolyhedraAhead).
    const auto holeAt = [&](size_t k) { return slots.moves[k].second; };
    for (size_t k = 0; k < slots.moves.size(); ++k) {
        geometry::prefetchPolyhedraAhead(body.primitives, holeAt, slots.moves.size(), k);
        const auto [from, hole] = slots.moves[k];
        body.primitives[size_t(hole)] = std::move(body.primitives[size_t(from)]);
        body.sourceFace[size_t(hole)] = body.sourceFace[size_t(from)];
    }
    body.primitives.resize(std::max(size_t(before), size_t(slots.size)));
    body.sourceFace.resize(body.primitives.size());
    const auto addedAt = [&](size_t k) { return slots.addedAt[k]; };
    for (int j = 0; j < added; ++j) {
        geometry::prefetchPolyhedraAhead(body.primitives, addedAt, size_t(added), size_t(j));
        place(j, slots.addedAt[size_t(j)]);
        body.sourceFace[size_t(slots.addedAt[size_t(j)])] = -1;
    }
    body.primitives.resize(size_t(slots.size));
    body.sourceFace.resize(size_t(slots.size));

    // Connections of two kept primitives, renumbered, in their order. The edit's count the
    // kept primitives in order, then the added ones.
    body.connections.swap(scratch.connections); // the old list's storage, for the next edit
    appendGainedConnections(body, edit, to, slots.addedAt, scratch.finalTo);

    applyFaceEdit(body.visual, edit);
    auto& visual = body.visual;
    visual.positions.insert(visual.positions.end(), edit.newVisualPositions.begin(), edit.newVisualPositions.end());
    body.globalIdCount = edit.globalIdCount;
    body.mass = edit.mass;
}

} // namespace

void applyRemainderEdit(geometry::PhysicalMesh& body, const RemainderEdit& e) {
    RemainderScratch scratch;
    applyEdit(body, e, int(e.added.size()), nullptr, scratch, TouchedList::Checked,
              [&](int j, int slot) { body.primitives[size_t(slot)] = e.added[size_t(j)]; });
}

void applyRemainderEdit(geometry::PhysicalMesh& body, const RemainderEdit& e,
                        std::vector<geometry::ConvexPolyhedron>&& pieces, const std::vector<int>& swapCarriers,
                        RemainderScratch* scratch, TouchedList touched) {
    RemainderScratch local;
    applyEdit(body, e, int(pieces.size()), &swapCarriers, scratch ? *scratch : local, touched,
              [&](int j, int slot) { body.primitives[size_t(slot)] = std::move(pieces[size_t(j)]); });
    pieces.clear();
}

void RemainderScratch::reserveFor(size_t primitives, size_t connectionCount, size_t faces, size_t ids) {
    auto room = [](size_t n) { return n + n / 4 + 64; }; // a rest may grow a little at a break
    // Written once (not only reserved), so that their pages are the body's set-up's: reserved
    // only, the first break touched them (page faults: 3 breaks of the 16k shell, 11 more in
    // applyRemainderEdit). The connection list's length stays, so the first break's list is
    // not zeroed again (keptConnections: perf samples of its zero fill, 116 -> 100).
    connections.resize(room(connectionCount));
    to.resize(room(primitives));
    finalTo.resize(room(primitives));
    faceTo.resize(room(faces));
    swapTable.resize(room(ids), -1); // -1 everywhere between edits (SwapTableEntries)
}

std::vector<int> swappedIds(const RemainderEdit& edit) {
    std::vector<int> swapped;
    swapped.reserve(2 * edit.idSwaps.size());
    for (const auto& [a, b] : edit.idSwaps) {
        swapped.push_back(a);
        swapped.push_back(b);
    }
    return swapped;
}

} // namespace shatter::fracture
