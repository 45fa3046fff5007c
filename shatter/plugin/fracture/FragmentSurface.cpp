#include <shatter/plugin/fracture/FragmentSurface.h>

#include <algorithm>
#include <cstdint>
#include <tuple>

namespace shatter::fracture {

namespace {

// Index k steps forward (backward) from `start` around a cycle of n (start < n, k <= n): the
// wrap by a comparison, not a modulo (a division), as these run for every edge of the body's
// surface and every vertex of every face a break emits.
size_t ahead(size_t start, size_t k, size_t n) { return start + k < n ? start + k : start + k - n; }
size_t behind(size_t start, size_t k, size_t n) { return start >= k ? start - k : start + n - k; }

} // namespace

FragmentSurface::FragmentSurface(const geometry::PhysicalMesh& body, const SurfaceIndex* index)
    : body_(body), visualCount_(int(body.visual.positions.size())), index_(index),
      wholeCount_(body.visual.faces.size(), 0), emittedIn_(body.visual.faces.size(), -1),
      emittedAt_(new int[body.visual.faces.size()]) {
    if (!index_) index_ = &own_.emplace(body);
}

int FragmentSurface::shownFace(const std::vector<int>& ids) const {
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

bool FragmentSurface::onSourceFace(int primitive, const std::vector<int>& ids) const {
    const int source = body_.sourceFace[size_t(primitive)];
    if (source < 0) return false;
    const auto& face = body_.visual.faces[size_t(source)];
    return std::all_of(ids.begin(), ids.end(), [&](int id) { return std::find(face.begin(), face.end(), id) != face.end(); });
}

FaceKind FragmentSurface::kindOf(int primitive, const std::vector<int>& ids) const {
    const bool allVisual = std::all_of(ids.begin(), ids.end(), [&](int id) { return id < visualCount_; });
    return allVisual && (onSourceFace(primitive, ids) || shownFace(ids) >= 0) ? FaceKind::Visual : FaceKind::Hidden;
}

bool FragmentSurface::sideFaceInside(const std::vector<int>& face, int source) const {
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

void FragmentSurface::emit(std::vector<int> face, bool crack, bool cancellable, FragmentFaces& out) {
    out.faces.push_back(std::move(face));
    out.crack.push_back(crack);
    cancellable_.push_back(cancellable);
}

FragmentFaces FragmentSurface::build(const std::vector<FragmentPart>& parts) {
    FragmentFaces out;
    cancellable_.clear();
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
    out.crack.reserve(room);
    cancellable_.reserve(room);

    std::vector<int> ids;
    // Asked once: SurfaceIndex::closed() is out of line, and was asked per face (~35 k calls,
    // ~0.6 M instructions in five events of the 16k shell).
    const bool closedBody = closed();
    // Sized once and written by index: push_back was an out-of-line call per part and per id
    // (~27 instructions each, ~60k calls in five events of the 16k shell).
    out.sourceFace.assign(parts.size(), -1);
    for (size_t i = 0; i < parts.size(); ++i) {
        const FragmentPart& part = parts[i];
        if (part.cut) {
            const CutFaces& s = *part.cut;
            for (int f = 0; f < s.faceCount(); ++f) {
                if (s.kinds[size_t(f)] == FaceKind::Hidden && !closedBody) continue;
                const int begin = s.faceStart[size_t(f)], end = s.faceStart[size_t(f) + 1];
                ids.resize(size_t(end - begin));
                for (int k = begin; k < end; ++k) ids[size_t(k - begin)] = s.ids[size_t(s.faceVertices[size_t(k)])];
                emit(ids, s.kinds[size_t(f)] == FaceKind::Crack, s.kinds[size_t(f)] != FaceKind::Visual, out);
            }
            continue;
        }
        const auto& primitive = body_.primitives[size_t(part.parent)];
        const int source = body_.sourceFace[size_t(part.parent)];
        const bool faceWhole = source >= 0 && wholeCount_[size_t(source)] == index_->primitivesOf(source);
        if (faceWhole) {
            if (emittedIn_[size_t(source)] != serial_) {
                emittedIn_[size_t(source)] = serial_;
                emittedAt_[size_t(source)] = int(out.faces.size());
                emit(body_.visual.faces[size_t(source)], false, false, out);
            }
            out.sourceFace[i] = emittedAt_[size_t(source)];
        }
        for (size_t f = 0; f < primitive.faces().size(); ++f) {
            const auto& face = primitive.faces()[f];
            ids.resize(face.size());
            // Only a face of visual ids can lie on a face of the body.
            bool allVisual = true;
            for (size_t k = 0; k < face.size(); ++k) {
                ids[k] = primitive.globalIds()[size_t(face[k])];
                allVisual &= ids[k] < visualCount_;
            }
            // Inside an open body's surface: nothing below shows it (a shell prism's bottom and
            // sides, most faces of a whole primitive).
            if (!allVisual && !closedBody) continue;
            // Its part of its source face: shown with the whole face, else on its own.
            if (allVisual && onSourceFace(part.parent, ids)) {
                if (!faceWhole) emit(ids, false, false, out);
                continue;
            }
            if (part.sourceOnly) continue;
            // A face the body shows as this primitive's own (a closed convex part's face, a
            // piece of an earlier break, an inner face a fragment of a closed body shows).
            if (allVisual && shownFace(ids) >= 0) {
                emit(ids, false, false, out);
                continue;
            }
            // Inside the body's surface: open to view once broken, unless it meets its twin.
            if (!closedBody) continue;
            if (faceWhole && !allVisual) {
                // Most of a large remainder: settle its inner faces here rather than by hashing.
                if (sideFaceInside(ids, source)) continue;
                const bool bottom = std::all_of(ids.begin(), ids.end(), [&](int id) { return id >= visualCount_; });
                emit(ids, false, !bottom, out);
                continue;
            }
            emit(ids, false, true, out);
        }
    }
    for (const auto& part : parts)
        if (!part.cut && body_.sourceFace[size_t(part.parent)] >= 0) --wholeCount_[size_t(body_.sourceFace[size_t(part.parent)])];
    cancelBackToBack(out);
    return out;
}

void FragmentSurface::cancelBackToBack(FragmentFaces& out) {
    // Sort the cancellable faces by a hash of their canonical id cycle and of its reverse;
    // a face cancels the first unmatched face that is its reverse.
    // Both readings hashed in one pass from the smallest id (found once, where a pass per
    // reading found it twice).
    auto hashesOf = [](const std::vector<int>& f) {
        const size_t n = f.size();
        size_t start = 0;
        for (size_t k = 1; k < n; ++k)
            if (f[k] < f[start]) start = k;
        std::uint64_t forward = 0xcbf29ce484222325ull ^ n, backward = forward;
        for (size_t k = 0; k < n; ++k) {
            forward = (forward ^ std::uint64_t(std::uint32_t(f[ahead(start, k, n)]))) * 0x100000001b3ull;
            backward = (backward ^ std::uint64_t(std::uint32_t(f[behind(start, k, n)]))) * 0x100000001b3ull;
        }
        return std::pair<std::uint64_t, std::uint64_t>(forward, backward);
    };
    auto sameReversed = [](const std::vector<int>& a, const std::vector<int>& b) {
        if (a.size() != b.size()) return false;
        const size_t n = a.size();
        const size_t startB = size_t(std::find(b.begin(), b.end(), a[0]) - b.begin());
        if (startB == n) return false;
        for (size_t k = 0; k < n; ++k)
            if (a[k] != b[behind(startB, k, n)]) return false;
        return true;
    };
    keys_.clear();
    backward_.resize(out.faces.size());
    for (size_t i = 0; i < out.faces.size(); ++i)
        if (cancellable_[i]) {
            const auto [forward, backward] = hashesOf(out.faces[i]);
            keys_.push_back({forward, int(i)});
            backward_[i] = backward;
        }
    if (keys_.size() < 2) return; // no pair to cancel: the faces stay as they are
    std::sort(keys_.begin(), keys_.end(),
              [](const FaceKey& a, const FaceKey& b) { return std::tie(a.hash, a.face) < std::tie(b.hash, b.face); });
    std::vector<char> gone(out.faces.size(), 0);
    for (size_t i = 0; i < out.faces.size(); ++i) {
        if (!cancellable_[i] || gone[i]) continue;
        // Faces whose forward reading matches this one read backwards.
        const std::uint64_t h = backward_[i];
        auto it = std::lower_bound(keys_.begin(), keys_.end(), h, [](const FaceKey& k, std::uint64_t v) { return k.hash < v; });
        for (; it != keys_.end() && it->hash == h; ++it) {
            const size_t j = size_t(it->face);
            if (j == i || gone[j] || !sameReversed(out.faces[i], out.faces[j])) continue;
            gone[i] = gone[j] = 1;
            break;
        }
    }
    size_t kept = 0;
    std::vector<int> newIndex(out.faces.size(), -1);
    for (size_t i = 0; i < out.faces.size(); ++i) {
        if (gone[i]) continue;
        newIndex[i] = int(kept);
        if (kept != i) {
            out.faces[kept] = std::move(out.faces[i]);
            out.crack[kept] = out.crack[i];
        }
        ++kept;
    }
    out.faces.resize(kept);
    out.crack.resize(kept);
    for (int& f : out.sourceFace)
        if (f >= 0) f = newIndex[size_t(f)];
}

} // namespace shatter::fracture
