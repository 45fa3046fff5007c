#include <shatter/plugin/fracture/SurfaceIndex.h>

#include <shatter/plugin/common/Prefetch.h>
#include <shatter/plugin/geometry/HoleFilling.h>

#include <algorithm>
#include <stdexcept>
#include <string>

namespace shatter::fracture {

namespace {

// Capacity for what a few breaks add (every break adds visual vertices, and one that gains
// more faces than it drops adds edges): grown by reallocation, a patch copied the whole edge
// list (~770 KB for the 16,000-face shell) into fresh pages. Reserved room is address space only until a patch writes
// there; reserved before the lists are filled, so nothing is copied at set-up either.
size_t withRoom(size_t size) { return size + size / 4 + 64; }

// Hints for patch's removal of faces[dropped[j]]: the face's vertex list kAhead * 2 faces on,
// then the heads of its corners' edge lists kAhead on (values read for a hint only choose what
// is loaded). A removal reads the face, its vertices and their lists one miss after the other,
// all over a 16k-face body's arrays. Weak evidence (rest16c, two interleaved perf pairs of the
// 16k shell x 64 cells): patch's samples 216 -> 206 and 184 -> 152. Hints alone, so inlined by
// force (see Prefetch.h).
[[gnu::always_inline]] inline void prefetchFaces(const std::vector<std::vector<int>>& faces,
                                                 const std::vector<int>& dropped, size_t j,
                                                 const std::vector<int>& firstEdge) {
    constexpr size_t kAhead = 8;
    if (j + 2 * kAhead < dropped.size()) {
        const std::vector<int>& face = faces[size_t(dropped[j + 2 * kAhead])];
        prefetchRange(face.data(), face.size() * sizeof(int));
    }
    if (j + kAhead >= dropped.size()) return;
    for (const int a : faces[size_t(dropped[j + kAhead])])
        if (a >= 0 && size_t(a) < firstEdge.size()) prefetchRange(&firstEdge[size_t(a)], sizeof(int));
}

} // namespace

SurfaceIndex::SurfaceIndex(const geometry::PhysicalMesh& body) {
    firstEdge_.reserve(withRoom(body.visual.positions.size()));
    firstEdge_.assign(body.visual.positions.size(), -1);
    primitivesOfFace_.reserve(withRoom(body.visual.faces.size()));
    primitivesOfFace_.assign(body.visual.faces.size(), 0);
    for (int f : body.sourceFace)
        if (f >= 0) ++primitivesOfFace_[size_t(f)];
    // Each corner's edge pushed on the front of its vertex's list, last corner first, so that
    // every list runs in face order (as a sort by first vertex would give).
    const auto& faces = body.visual.faces;
    for (const auto& face : faces) edgeCount_ += int(face.size());
    edges_.reserve(withRoom(size_t(edgeCount_)));
    edges_.resize(size_t(edgeCount_));
    // Through plain pointers: the vectors' members would be reloaded after every store.
    int* first = firstEdge_.data();
    Edge* edges = edges_.data();
    int e = edgeCount_;
    for (size_t f = faces.size(); f-- > 0;) {
        const int* v = faces[f].data();
        const int n = int(faces[f].size());
        if (n == 0) continue;
        e -= n;
        int to = v[0]; // the face's closing edge v[n - 1]→v[0] first
        for (int k = n - 1; k >= 0; --k) {
            const int a = v[k];
            edges[e + k] = {to, int(f), first[a]};
            first[a] = e + k;
            to = a;
        }
    }
    closed(); // at set-up, not at the first break
}

bool SurfaceIndex::closed() const {
    if (closed_ != Closed::Unknown) return closed_ == Closed::Yes;
    // Once each way on a mesh as loaded; a fragment of a closed shell also shows its
    // primitives' inner faces, and where two extruded faces meet at a crease the crease edge
    // is used twice each way (the two primitives' side faces under it overlap).
    bool closed = edgeCount_ > 0;
    for (int a = 0; a < visualCount() && closed; ++a)
        for (int k = firstEdge_[size_t(a)]; k >= 0 && closed; k = edges_[size_t(k)].next) {
            const int b = edges_[size_t(k)].to;
            closed = edgeCount(a, b) == edgeCount(b, a);
        }
    closed_ = closed ? Closed::Yes : Closed::No;
    return closed;
}

int SurfaceIndex::edgeCount(int a, int b) const {
    int n = 0;
    for (int e = firstEdge_[size_t(a)]; e >= 0; e = edges_[size_t(e)].next) n += edges_[size_t(e)].to == b;
    return n;
}

int SurfaceIndex::faceWithEdge(int a, int b) const {
    for (int e = firstEdge_[size_t(a)]; e >= 0; e = edges_[size_t(e)].next)
        if (edges_[size_t(e)].to == b) return edges_[size_t(e)].face;
    return -1;
}

void SurfaceIndex::link(int a, int b, int face) {
    int e = freeEdge_;
    if (e >= 0) {
        freeEdge_ = edges_[size_t(e)].next;
    } else {
        e = int(edges_.size());
        edges_.push_back({});
    }
    // After every edge of a face up to this one: the list stays in face order, and a face's
    // own edges from a (added corner by corner) in corner order.
    int before = -1;
    for (int k = firstEdge_[size_t(a)]; k >= 0 && edges_[size_t(k)].face <= face; k = edges_[size_t(k)].next) before = k;
    int& slot = before < 0 ? firstEdge_[size_t(a)] : edges_[size_t(before)].next;
    edges_[size_t(e)] = {b, face, slot};
    slot = e;
    ++edgeCount_;
}

void SurfaceIndex::unlink(int a, int b, int face) {
    for (int* slot = &firstEdge_[size_t(a)]; *slot >= 0; slot = &edges_[size_t(*slot)].next) {
        const int e = *slot;
        if (edges_[size_t(e)].to != b || edges_[size_t(e)].face != face) continue;
        *slot = edges_[size_t(e)].next;
        edges_[size_t(e)].next = freeEdge_;
        freeEdge_ = e;
        --edgeCount_;
        return;
    }
    throw std::logic_error("SurfaceIndex: no edge " + std::to_string(a) + "→" + std::to_string(b) + " of face " +
                           std::to_string(face) + " (the index is not the body's)");
}

void SurfaceIndex::addFace(const std::vector<int>& face, int index) {
    const size_t n = face.size();
    for (size_t k = 0; k < n; ++k) link(face[k], face[k + 1 < n ? k + 1 : 0], index);
}

void SurfaceIndex::removeFace(const std::vector<int>& face, int index) {
    const size_t n = face.size();
    for (size_t k = 0; k < n; ++k) unlink(face[k], face[k + 1 < n ? k + 1 : 0], index);
}

void SurfaceIndex::patch(const geometry::PhysicalMesh& body, const RemainderEdit& edit) {
    // Source faces: the removed primitives' and those the kept ones lose (applyRemainderEdit
    // sets them to -1); the others follow their face.
    for (int p : edit.removed)
        if (const int f = body.sourceFace[size_t(p)]; f >= 0) --primitivesOfFace_[size_t(f)];
    for (int p : edit.lostSourceFace)
        if (const int f = body.sourceFace[size_t(p)]; f >= 0) --primitivesOfFace_[size_t(f)];
    // The faces in applyFaceEdit's places: the gained ones take the dropped ones', the last
    // faces fill the holes left.
    closed_ = Closed::Unknown;
    const auto& faces = body.visual.faces;
    const geometry::HoleFilling slots = geometry::fillHoles(faceCount(), edit.droppedFaces, int(edit.faces.size()));
    for (size_t j = 0; j < edit.droppedFaces.size(); ++j) {
        prefetchFaces(faces, edit.droppedFaces, j, firstEdge_);
        removeFace(faces[size_t(edit.droppedFaces[j])], edit.droppedFaces[j]);
    }
    for (const auto& [from, hole] : slots.moves) {
        removeFace(faces[size_t(from)], from);
        addFace(faces[size_t(from)], hole);
        primitivesOfFace_[size_t(hole)] = primitivesOfFace_[size_t(from)];
    }
    // The new visual vertices (the edit's faces are in its final ids: visual ones first).
    firstEdge_.resize(firstEdge_.size() + edit.newVisualPositions.size(), -1);
    primitivesOfFace_.resize(size_t(std::max(faceCount(), slots.size)));
    for (size_t j = 0; j < edit.faces.size(); ++j) {
        const int at = slots.addedAt[j];
        primitivesOfFace_[size_t(at)] = 0; // the added pieces have no source face
        addFace(edit.faces[j], at);
    }
    primitivesOfFace_.resize(size_t(slots.size));
}

bool SurfaceIndex::operator==(const SurfaceIndex& other) const {
    if (visualCount() != other.visualCount() || edgeCount_ != other.edgeCount_ || closed() != other.closed() ||
        primitivesOfFace_ != other.primitivesOfFace_)
        return false;
    for (int a = 0; a < visualCount(); ++a) {
        int e = firstEdge(a), o = other.firstEdge(a);
        for (; e >= 0 && o >= 0; e = edge(e).next, o = other.edge(o).next)
            if (edge(e).to != other.edge(o).to || edge(e).face != other.edge(o).face) return false;
        if (e >= 0 || o >= 0) return false;
    }
    return true;
}

} // namespace shatter::fracture
