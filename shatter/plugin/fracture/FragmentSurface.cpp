#include <shatter/plugin/fracture/FragmentSurface.h>

#include <shatter/plugin/common/Prefetch.h>

#include <algorithm>
#include <bit>
#include <cstdint>

namespace shatter::fracture {

namespace {

// Index k steps forward (backward) from `start` around a cycle of n (start < n, k <= n): the
// wrap by a comparison, not a modulo (a division), as these run for every edge of the body's
// surface and every vertex of every face a break emits.
size_t ahead(size_t start, size_t k, size_t n) { return start + k < n ? start + k : start + k - n; }
size_t behind(size_t start, size_t k, size_t n) { return start >= k ? start - k : start + n - k; }

// A hash of the face's id set: a sum over its ids, so every reading of the cycle, either way
// round, has the same one (no search for the smallest id, one hash where a face had two:
// its readings forward and backward). Each id is mixed so that sets of equal sums rarely
// meet; a hash shared by faces that are not reverses costs a comparison, never a result.
std::uint64_t idSetHash(std::span<const int> ids) {
    std::uint64_t h = ids.size();
    for (int id : ids) {
        const std::uint64_t x = std::uint64_t(std::uint32_t(id)) * 0x9e3779b97f4a7c15ull;
        h += x ^ (x >> 29);
    }
    return h;
}

// Starts loading a part's ids and faces (FragmentSurface::build asks kPartsAhead parts
// ahead of emitWhole and emitCut): a whole part's are scattered over the body's heap, a cut
// part's were written by the cutting, and both stalled on them. A whole part's ids, indices
// and face starts, all lines of each: a prism's indices are 72 bytes, often two lines, and
// emitWhole stalled on the starts too (its self samples 61-86 -> 22-36 in 200 events of the
// 16k shell, perf). A cut part's, the first line of each (emitCut's 31-50 -> 18-24 in 150;
// all lines cost more instructions for no time measured). Hints alone, so inlined by force
// (see Prefetch.h).
constexpr size_t kPartsAhead = 4;
[[gnu::always_inline]] inline void prefetchPart(const FragmentPart& part,
                                                const std::vector<geometry::ConvexPolyhedron>& primitives) {
    const auto ints = [](std::span<const int> v) { return v.size() * sizeof(int); };
    if (part.cut) {
        const CutFaces& cut = *part.cut;
        __builtin_prefetch(cut.faceStart.data());
        __builtin_prefetch(cut.faceVertices.data());
        __builtin_prefetch(cut.kinds.data());
        __builtin_prefetch(cut.ids.data());
        return;
    }
    const geometry::ConvexPolyhedron& primitive = primitives[size_t(part.parent)];
    const geometry::FaceList& faces = primitive.faces();
    prefetchRange(primitive.globalIds().data(), ints(primitive.globalIds()));
    prefetchRange(faces.indices().data(), ints(faces.indices()));
    prefetchRange(faces.starts().data(), ints(faces.starts()));
}

} // namespace

FragmentSurface::FragmentSurface(const geometry::PhysicalMesh& body, const SurfaceIndex* index)
    : body_(body), visualCount_(int(body.visual.positions.size())), index_(index),
      wholeCount_(body.visual.faces.size(), 0), emittedIn_(body.visual.faces.size(), -1),
      emittedAt_(new int[body.visual.faces.size()]) {
    if (!index_) index_ = &own_.emplace(body);
}

int FragmentSurface::shownFace(std::span<const int> ids) const {
    const size_t n = ids.size();
    if (n < 3 || ids[0] >= visualCount_ || ids[1] >= visualCount_) return -1;
    for (int e = index_->firstEdge(ids[0]); e >= 0; e = index_->edge(e).next) {
        if (index_->edge(e).to != ids[1]) continue;
        const auto& face = body_.visual.faces[size_t(index_->edge(e).face)];
        if (face.size() != n) continue;
        const size_t start = size_t(std::find(face.begin(), face.end(), ids[0]) - face.begin());
        bool same = true;
        for (size_t k = 0; k < n && same; ++k) same = face[ahead(start, k, n)] == ids[k];
        if (same) return index_->edge(e).face;
    }
    return -1;
}

bool FragmentSurface::onSourceFace(int primitive, std::span<const int> ids) const {
    const int source = body_.sourceFace[size_t(primitive)];
    if (source < 0) return false;
    const auto& face = body_.visual.faces[size_t(source)];
    return std::all_of(ids.begin(), ids.end(), [&](int id) { return std::find(face.begin(), face.end(), id) != face.end(); });
}

FaceKind FragmentSurface::kindOf(int primitive, std::span<const int> ids) const {
    const bool allVisual = std::all_of(ids.begin(), ids.end(), [&](int id) { return id < visualCount_; });
    return allVisual && (onSourceFace(primitive, ids) || shownFace(ids) >= 0) ? FaceKind::Visual : FaceKind::Hidden;
}

bool FragmentSurface::sideFaceInside(std::span<const int> face, int source) const {
    // A side face of a prism carries two visual ids, consecutive (x→y, the prism's top edge
    // read backwards); the twin is the side face of the prism across that edge.
    int x = -1, y = -1, visual = 0;
    for (size_t k = 0; k < face.size(); ++k) {
        const int a = face[k], b = face[ahead(k, 1, face.size())];
        visual += a < visualCount_;
        if (a < visualCount_ && b < visualCount_) x = a, y = b;
    }
    if (visual != 2 || x < 0) return false;
    const int across = index_->faceWithEdge(x, y);
    // No face holds x→y: an inner edge of the source face (split into triangles), whose other
    // triangle's prism is whole here too since the whole face is.
    if (across < 0) return index_->faceWithEdge(y, x) != source;
    return faceWholeHere(across);
}

// out.crack is sized (false) for every face the parts may show (prepare) and cut to the
// faces shown after: only a crack face's bit is written (a push_back per face was ~19
// instructions).
void FragmentSurface::emit(std::span<const int> face, bool crack, bool cancellable, FragmentFaces& out) {
    if (crack) out.crack[out.faces.size()] = true;
    if (cancellable) keys_.push_back({idSetHash(face), int(out.faces.size()), -1, -1, false});
    out.faces.emplace_back(face.begin(), face.end());
}


FragmentFaces FragmentSurface::build(const std::vector<FragmentPart>& parts) {
    FragmentFaces out;
    prepare(parts, out);
    // Asked once: SurfaceIndex::closed() is out of line, and was asked per face (~35 k calls,
    // ~0.6 M instructions in five events of the 16k shell).
    const bool closedBody = closed();
    // Sized once and written by index: push_back was an out-of-line call per part and per id
    // (~27 instructions each, ~60k calls in five events of the 16k shell).
    out.sourceFace.assign(parts.size(), -1);
    for (size_t i = 0; i < parts.size(); ++i) {
        if (i + kPartsAhead < parts.size()) prefetchPart(parts[i + kPartsAhead], body_.primitives);
        if (parts[i].cut) emitCut(*parts[i].cut, closedBody, out);
        else emitWhole(parts[i], closedBody, out.sourceFace[i], out);
    }
    out.crack.resize(out.faces.size());
    for (const auto& part : parts)
        if (!part.cut && body_.sourceFace[size_t(part.parent)] >= 0) --wholeCount_[size_t(body_.sourceFace[size_t(part.parent)])];
    cancelBackToBack(out);
    return out;
}

void FragmentSurface::prepare(const std::vector<FragmentPart>& parts, FragmentFaces& out) {
    keys_.clear();
    ++serial_;
    // Room for every face the parts may show (a whole part: its faces and its source face), so
    // that the lists never grow by reallocation.
    size_t room = 0;
    for (const auto& part : parts) {
        if (part.cut) {
            room += size_t(part.cut->faceCount());
            continue;
        }
        room += body_.primitives[size_t(part.parent)].faces().size() + 1;
        if (body_.sourceFace[size_t(part.parent)] >= 0) ++wholeCount_[size_t(body_.sourceFace[size_t(part.parent)])];
    }
    out.faces.reserve(room);
    out.crack.assign(room, false);
}

void FragmentSurface::emitCut(const CutFaces& s, bool closedBody, FragmentFaces& out) {
    for (int f = 0; f < s.faceCount(); ++f) {
        const FaceKind kind = s.kinds[size_t(f)];
        if (kind == FaceKind::Hidden && !closedBody) continue;
        const int begin = s.faceStart[size_t(f)], end = s.faceStart[size_t(f) + 1];
        const std::span<int> ids = idBuffer(size_t(end - begin));
        for (int k = begin; k < end; ++k) ids[size_t(k - begin)] = s.ids[size_t(s.faceVertices[size_t(k)])];
        emit(ids, kind == FaceKind::Crack, kind != FaceKind::Visual, out);
    }
}

void FragmentSurface::emitWhole(const FragmentPart& part, bool closedBody, int& sourceFace, FragmentFaces& out) {
    const auto& primitive = body_.primitives[size_t(part.parent)];
    const int source = body_.sourceFace[size_t(part.parent)];
    const WholePart whole{part.parent, source, part.sourceOnly,
                          source >= 0 && wholeCount_[size_t(source)] == index_->primitivesOf(source)};
    if (whole.faceWhole) {
        if (emittedIn_[size_t(source)] != serial_) {
            emittedIn_[size_t(source)] = serial_;
            emittedAt_[size_t(source)] = int(out.faces.size());
            emit(body_.visual.faces[size_t(source)], false, false, out);
        }
        sourceFace = emittedAt_[size_t(source)];
    }
    for (size_t f = 0; f < primitive.faces().size(); ++f) {
        const auto& face = primitive.faces()[f];
        const std::span<int> ids = idBuffer(face.size());
        // Only a face of visual ids can lie on a face of the body.
        bool allVisual = true;
        for (size_t k = 0; k < face.size(); ++k) {
            ids[k] = primitive.globalIds()[size_t(face[k])];
            allVisual &= ids[k] < visualCount_;
        }
        // Inside an open body's surface: nothing below shows it (a shell prism's bottom and
        // sides, most faces of a whole primitive).
        if (!allVisual && !closedBody) continue;
        emitWholeFace(whole, ids, allVisual, closedBody, out);
    }
}

void FragmentSurface::emitWholeFace(const WholePart& whole, std::span<const int> ids, bool allVisual, bool closedBody,
                                    FragmentFaces& out) {
    // Its part of its source face: shown with the whole face, else on its own.
    if (allVisual && onSourceFace(whole.parent, ids)) {
        if (!whole.faceWhole) emit(ids, false, false, out);
        return;
    }
    if (whole.sourceOnly) return;
    // A face the body shows as this primitive's own (a closed convex part's face, a piece of
    // an earlier break, an inner face a fragment of a closed body shows).
    if (allVisual && shownFace(ids) >= 0) {
        emit(ids, false, false, out);
        return;
    }
    // Inside the body's surface: open to view once broken, unless it meets its twin.
    if (!closedBody) return;
    if (whole.faceWhole && !allVisual) {
        // Most of a large remainder: settle its inner faces here rather than by hashing.
        if (sideFaceInside(ids, whole.source)) return;
        const bool bottom = std::all_of(ids.begin(), ids.end(), [&](int id) { return id >= visualCount_; });
        emit(ids, false, !bottom, out);
        return;
    }
    emit(ids, false, true, out);
}

void FragmentSurface::cancelBackToBack(FragmentFaces& out) {
    // A face cancels the first face (in face order) still there that is its reverse. A face's
    // reverse has its id set, so its hash: only faces of one hash are compared (most hashes
    // are one face's). Faces run in face order within a hash's run and meet only faces of
    // their run, so the pairs are those of one pass over all faces.
    if (keys_.size() < 2) return; // no pair to cancel: the faces stay as they are
    groupKeysByHash();
    cancelled_.clear();
    for (int first : sharedRuns_) {
        run_.clear();
        for (int k = first; k >= 0; k = keys_[size_t(k)].nextSame) run_.push_back(k);
        cancelWithin(run_, out);
    }
    if (!cancelled_.empty()) dropCancelled(out);
}

void FragmentSurface::groupKeysByHash() {
    // A table of at least twice the keys, by the hash's low bits (a sort of the keys by hash
    // was ~0.5 M instructions in five events of the 16k shell).
    const size_t size = std::bit_ceil(2 * keys_.size()), mask = size - 1;
    slots_.assign(size, -1);
    sharedRuns_.clear();
    for (size_t k = 0; k < keys_.size(); ++k) {
        FaceKey& key = keys_[k];
        size_t slot = size_t(key.hash) & mask;
        while (slots_[slot] >= 0 && keys_[size_t(slots_[slot])].hash != key.hash) slot = (slot + 1) & mask;
        if (slots_[slot] < 0) {
            slots_[slot] = int(k);
            key.lastSame = int(k);
            continue;
        }
        FaceKey& first = keys_[size_t(slots_[slot])];
        if (first.nextSame < 0) sharedRuns_.push_back(slots_[slot]);
        keys_[size_t(first.lastSame)].nextSame = int(k);
        first.lastSame = int(k);
    }
}

void FragmentSurface::cancelWithin(const std::vector<int>& run, const FragmentFaces& out) {
    auto sameReversed = [](const std::vector<int>& a, const std::vector<int>& b) {
        if (a.size() != b.size()) return false;
        const size_t n = a.size();
        const size_t startB = size_t(std::find(b.begin(), b.end(), a[0]) - b.begin());
        if (startB == n) return false;
        for (size_t k = 0; k < n; ++k)
            if (a[k] != b[behind(startB, k, n)]) return false;
        return true;
    };
    for (int i : run) {
        FaceKey& a = keys_[size_t(i)];
        if (a.gone) continue;
        for (int j : run) {
            FaceKey& b = keys_[size_t(j)];
            if (j == i || b.gone || !sameReversed(out.faces[size_t(a.face)], out.faces[size_t(b.face)])) continue;
            a.gone = b.gone = true;
            cancelled_.push_back(a.face);
            cancelled_.push_back(b.face);
            break;
        }
    }
}

void FragmentSurface::dropCancelled(FragmentFaces& out) {
    std::sort(cancelled_.begin(), cancelled_.end());
    size_t kept = 0, next = 0;
    for (size_t i = 0; i < out.faces.size(); ++i) {
        if (next < cancelled_.size() && size_t(cancelled_[next]) == i) {
            ++next;
            continue;
        }
        if (kept != i) {
            out.faces[kept] = std::move(out.faces[i]);
            out.crack[kept] = out.crack[i];
        }
        ++kept;
    }
    out.faces.resize(kept);
    out.crack.resize(kept);
    // A source face is never cancellable: it moves back by the cancelled faces before it.
    for (int& f : out.sourceFace)
        if (f >= 0) f -= int(std::lower_bound(cancelled_.begin(), cancelled_.end(), f) - cancelled_.begin());
}

} // namespace shatter::fracture
