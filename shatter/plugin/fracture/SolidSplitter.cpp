#include <shatter/plugin/fracture/SolidSplitter.h>

#include <algorithm>
#include <cmath>
#include <optional>

namespace shatter::fracture {

namespace {

// One part while writeParts writes it: through pointers into room for the most it can hold
// (every vertex source; per face its vertices and a crossing per edge), then cut to what it
// holds. Not cleared first: every entry kept is written here, and a scratch solid resized from
// its last size (not from empty) zeroes only what it grows by.
class PartWriter {
public:
    // Vertex sources are the solid's vertices, then count + crossing index (room for a crossing
    // per face slot). A new vertex's id is left for the caller: the crossings are found while
    // the parts are written, and their ids asked for after (in the order they were made).
    // `map` (vertex source → index in the part) is -1 for the solid's vertices here; the caller
    // sets a crossing's entry to -1 when it makes it. `sources` (index in the part → vertex
    // source) and `capEdges` (the cut-face edges) are filled when not null.
    // Inlined: out of line, the writer's address went to the call and every member was then
    // kept in memory through the face loop (-0.43 M instructions a break, callgrind).
    [[gnu::always_inline]] PartWriter(const Solid& solid, const std::vector<Eigen::Vector3d>& newPositions, Solid& out,
                                      std::vector<int>& map, std::vector<int>* sources,
                                      std::vector<std::pair<int, int>>* capEdges)
        : solid_(solid), count_(int(solid.positions.size())), newPositions_(newPositions), out_(out),
          sources_(sources), capEdges_(capEdges) {
        const size_t sourceCount = size_t(count_) + solid.faceVertices.size();
        map.resize(sourceCount);
        std::fill_n(map.data(), count_, -1);
        map_ = map.data();
        if (sources_) sources_->clear();
        if (capEdges_) capEdges_->clear();
        out.faceStart.assign(1, 0);
        out.kinds.clear();
        out.positions.resize(sourceCount);
        out.ids.resize(sourceCount);
        out.faceVertices.resize(2 * solid.faceVertices.size());
        positions_ = out.positions.data();
        ids_ = out.ids.data();
        faceVertices_ = out.faceVertices.data();
    }

    // (Inlined: called per vertex of every face, a call each cost more than the pass saves.)
    [[gnu::always_inline]] void beginFace() {
        start_ = slot_;
        first_ = last_ = -1;
        skipped_ = skippedBeforeFirst_ = false;
    }
    // The face's next vertex source on this part's side.
    [[gnu::always_inline]] void keep(int source) {
        const int index = indexOf(source);
        faceVertices_[slot_++] = index;
        // An edge between two kept vertices with dropped ones between them lies on the plane:
        // the cut face has it the other way round.
        if (capEdges_ && skipped_ && last_ >= 0 && last_ != index) capEdges_->emplace_back(index, last_);
        if (first_ < 0) {
            first_ = index;
            skippedBeforeFirst_ = skipped_;
        }
        last_ = index;
        skipped_ = false;
    }
    // A vertex of the face on the other side.
    [[gnu::always_inline]] void skip() { skipped_ = true; }
    [[gnu::always_inline]] void endFace(FaceKind kind) {
        if (capEdges_ && (skipped_ || skippedBeforeFirst_) && first_ >= 0 && last_ != first_)
            capEdges_->emplace_back(first_, last_);
        if (slot_ - start_ >= 3) { // Solid::addFace, with the face's end known here
            out_.faceStart.push_back(slot_);
            out_.kinds.push_back(kind);
        } else {
            slot_ = start_; // touches the plane in a point or an edge only
        }
    }
    void finish() {
        out_.positions.resize(size_t(vertexCount_));
        out_.ids.resize(size_t(vertexCount_));
        out_.faceVertices.resize(size_t(slot_));
    }

private:
    // The part's index of a vertex source, added on first use.
    [[gnu::always_inline]] int indexOf(int source) {
        int& index = map_[source];
        if (index < 0) {
            index = vertexCount_++;
            if (source < count_) {
                positions_[index] = solid_.positions[size_t(source)];
                ids_[index] = solid_.ids[size_t(source)];
            } else {
                positions_[index] = newPositions_[size_t(source - count_)]; // its id set after
            }
            if (sources_) sources_->push_back(source);
        }
        return index;
    }

    const Solid& solid_;
    const int count_;
    const std::vector<Eigen::Vector3d>& newPositions_;
    Solid& out_;
    std::vector<int>* sources_;
    std::vector<std::pair<int, int>>* capEdges_;
    int* map_;
    Eigen::Vector3d* positions_;
    int* ids_;
    int* faceVertices_;
    int vertexCount_ = 0, slot_ = 0;
    int start_ = 0, first_ = -1, last_ = -1; // the face being written
    bool skipped_ = false, skippedBeforeFirst_ = false;
};

// The crossings of the edges the plane crosses, made as writeParts meets them. Each crossed
// edge is met twice (once by each of its faces): the first makes it, so the crossings are
// numbered in face-slot order. Per vertex, its last crossing to a higher index (lastFrom), the
// crossings from it chained by Crossing::next: an edge's second face finds its crossing in a
// chain of one or two. Through pointers, and inlined: as a lambda it was kept in registers.
class CrossingFinder {
public:
    using Crossing = SolidSplitter::Crossing;
    // `lastFrom` is -1 per vertex of the solid; `made` has room for a crossing per face slot.
    // A crossing's entries in mapDown and mapUp (when not null) are set to -1 when it is made.
    [[gnu::always_inline]] CrossingFinder(const Solid& solid, const double* distance, Crossing* made, int* lastFrom,
                                          std::vector<Eigen::Vector3d>& newPositions, int* mapDown, int* mapUp)
        : count_(int(solid.positions.size())), position_(solid.positions.data()), distance_(distance), made_(made),
          lastFrom_(lastFrom), newPositions_(newPositions), mapDown_(mapDown), mapUp_(mapUp) {}

    // The index of the crossing on edge (a, b), made when not yet.
    [[gnu::always_inline]] int at(int a, int b) {
        if (b < a) std::swap(a, b);
        int c = lastFrom_[a];
        while (c >= 0 && made_[c].b != b) c = made_[c].next;
        if (c < 0) {
            // Always from the lower index: both faces of the edge, and both parts, get the same bits.
            const double t = distance_[a] / (distance_[a] - distance_[b]);
            const Eigen::Vector3d& pa = position_[a];
            newPositions_.push_back(pa + t * (position_[b] - pa));
            c = madeCount_++;
            made_[c] = {b, lastFrom_[a]};
            lastFrom_[a] = c;
            mapDown_[count_ + c] = -1;
            if (mapUp_) mapUp_[count_ + c] = -1;
        }
        return c;
    }

private:
    const int count_;
    const Eigen::Vector3d* position_;
    const double* distance_;
    Crossing* made_;
    int* lastFrom_;
    std::vector<Eigen::Vector3d>& newPositions_;
    int* mapDown_;
    int* mapUp_;
    int madeCount_ = 0;
};

// One face's slots [begin, end) into the part below and, with kAbove, the part above. Slot k:
// its vertex a, then the crossing on the edge from a to the next vertex b (the first one after
// the last slot); the sides carried from slot to slot in registers.
template <bool kAbove>
[[gnu::always_inline]] inline void writeFace(const int* vertices, int begin, int end, const signed char* side,
                                             int count, CrossingFinder& crossing, PartWriter& down, PartWriter& up) {
    down.beginFace();
    if constexpr (kAbove) up.beginFace();
    const int first = begin < end ? vertices[begin] : 0, firstSide = begin < end ? side[first] : 0;
    int a = first, sa = firstSide;
    for (int k = begin; k < end; ++k) {
        if (sa <= 0) down.keep(a);
        else down.skip();
        if constexpr (kAbove) {
            if (sa >= 0) up.keep(a);
            else up.skip();
        }
        const bool closing = k + 1 == end;
        const int b = closing ? first : vertices[k + 1], sb = closing ? firstSide : side[b];
        if (sa * sb < 0) {
            const int c = crossing.at(a, b);
            down.keep(count + c);
            if constexpr (kAbove) up.keep(count + c);
        }
        a = b;
        sa = sb;
    }
}

} // namespace

template <bool kAbove>
void SolidSplitter::writeParts(const Solid& solid, Solid& below, Solid* above) {
    const int count = int(solid.positions.size());
    const size_t slots = solid.faceVertices.size();
    newPositions_.clear();
    // The below part's vertex sources only map the cut face to the part above.
    PartWriter down(solid, newPositions_, below, mapBelow_, kAbove ? &sourceBelow_ : nullptr, &capEdges_);
    std::optional<PartWriter> upRoom; // the part above, when written
    if constexpr (kAbove) upRoom.emplace(solid, newPositions_, *above, mapAbove_, nullptr, nullptr);
    PartWriter& up = *upRoom; // (without kAbove: never used)
    // The crossed edges, found in the same pass (a pass of their own over every face slot
    // cost as much as writing a part): room for one per slot (crossings_ only grows).
    if (crossings_.size() < slots) crossings_.resize(slots);
    lastFrom_.assign(size_t(count), -1);
    CrossingFinder crossing(solid, distance_.data(), crossings_.data(), lastFrom_.data(), newPositions_,
                            mapBelow_.data(), kAbove ? mapAbove_.data() : nullptr);
    const signed char* side = side_.data();
    const int* vertices = solid.faceVertices.data();
    const int faceCount = solid.faceCount();
    for (int f = 0; f < faceCount; ++f) {
        const int begin = solid.faceStart[size_t(f)], end = solid.faceStart[size_t(f) + 1];
        writeFace<kAbove>(vertices, begin, end, side, count, crossing, down, up);
        down.endFace(solid.kinds[size_t(f)]);
        if constexpr (kAbove) up.endFace(solid.kinds[size_t(f)]);
    }
    down.finish();
    if constexpr (kAbove) up.finish();
}

bool SolidSplitter::chainCap(int vertexCount) {
    cap_.clear();
    if (capEdges_.size() < 3) return false;
    // Each vertex's way on, in an array by vertex (-1: none): the walk was a scan of every edge
    // per step, quadratic in the cut face's size (1.76 -> 1.65 M instructions for the 8k cut
    // faces of five 16k-shell breaks, of four edges on average).
    if (capNext_.size() < size_t(vertexCount)) capNext_.resize(size_t(vertexCount), -1);
    int* next = capNext_.data();
    // Two ways on from a vertex: not a simple loop, whether the walk meets that vertex or not
    // (a loop that closes without it has at most all edges but its two).
    bool simple = true;
    for (const auto& [a, b] : capEdges_) {
        if (next[a] >= 0) simple = false;
        else next[a] = b;
    }
    bool closed = false;
    if (simple) {
        const int start = capEdges_.front().first;
        int v = start;
        do {
            cap_.push_back(v);
            v = next[v];
        } while (v >= 0 && v != start && cap_.size() <= capEdges_.size());
        closed = v == start && cap_.size() == capEdges_.size();
    }
    for (const auto& edge : capEdges_) next[edge.first] = -1; // all -1 again for the next cut
    return closed;
}

// (Inlined, as assignIds and closeParts: out of line, their calls and reloads cost ~0.3 M
// instructions in five 16k-shell breaks.)
[[gnu::always_inline]] inline SolidSplitter::Outcome SolidSplitter::measure(const Solid& solid,
                                                                            const Eigen::Vector3d& n, double d,
                                                                            double tolerance) {
    const int count = int(solid.positions.size());
    distance_.resize(size_t(count));
    side_.resize(size_t(count));
    // Through locals: a store to side_ (a char) may alias anything, so the normal and every
    // vector's members were reloaded at each vertex (~30 instructions, 37k vertices a break).
    const Eigen::Vector3d normal = n;
    const Eigen::Vector3d* position = solid.positions.data();
    double* distance = distance_.data();
    signed char* side = side_.data();
    bool anyBelow = false, anyAbove = false;
    for (int i = 0; i < count; ++i) {
        const double s = normal.dot(position[i]) - d;
        distance[i] = s;
        side[i] = s > tolerance ? 1 : (s < -tolerance ? -1 : 0);
        anyBelow |= side[i] < 0;
        anyAbove |= side[i] > 0;
    }
    return !anyAbove ? Outcome::Below : (!anyBelow ? Outcome::Above : Outcome::Split);
}

[[gnu::always_inline]] inline void SolidSplitter::assignIds(NewVertexIds& ids, int count, Solid& below,
                                                            Solid* above) const {
    const int* mapDown = mapBelow_.data();
    const int* mapUp = above ? mapAbove_.data() : nullptr;
    for (size_t c = 0; c < newPositions_.size(); ++c) {
        const int id = ids.idAt(newPositions_[c]);
        if (const int i = mapDown[size_t(count) + c]; i >= 0) below.ids[size_t(i)] = id;
        if (mapUp)
            if (const int i = mapUp[size_t(count) + c]; i >= 0) above->ids[size_t(i)] = id;
    }
}

[[gnu::always_inline]] inline void SolidSplitter::closeParts(Solid& below, Solid* above) const {
    below.faceVertices.insert(below.faceVertices.end(), cap_.begin(), cap_.end());
    below.addFace(FaceKind::Crack);
    if (!above) return;
    // The part above gets the same cut face reversed, from the same first vertex, so both
    // parts triangulate it alike and their volumes add up to the solid's.
    auto aboveIndex = [&](int belowIndex) { return mapAbove_[size_t(sourceBelow_[size_t(belowIndex)])]; };
    above->faceVertices.push_back(aboveIndex(cap_.front()));
    for (size_t k = cap_.size() - 1; k >= 1; --k) above->faceVertices.push_back(aboveIndex(cap_[k]));
    above->addFace(FaceKind::Crack);
}

SolidSplitter::Outcome SolidSplitter::split(const Solid& solid, const Eigen::Vector3d& n, double d, double tolerance,
                                            NewVertexIds& ids, Solid& below, Solid* above) {
    if (const Outcome sides = measure(solid, n, d, tolerance); sides != Outcome::Split) return sides;
    // Both parts in one pass over the faces (each part's vertices and faces come out in the
    // order a pass of its own gave them). The part above is written even when the cut face
    // below does not close and neither part is used.
    if (above) writeParts<true>(solid, below, above);
    else writeParts<false>(solid, below, nullptr);
    // The new vertices' ids, asked for in the order the crossings were made (that order numbers
    // them), then written where each part has the crossing.
    assignIds(ids, int(solid.positions.size()), below, above);
    if (!chainCap(int(below.positions.size()))) {
        // A cut face that does not close (round-off on a nearly degenerate solid): keep the
        // solid whole on the side holding most of it rather than make a broken piece.
        double downward = 0.0, upward = 0.0;
        for (double s : distance_) (s < 0.0 ? downward : upward) += std::abs(s);
        return downward >= upward ? Outcome::Below : Outcome::Above;
    }
    closeParts(below, above);
    return Outcome::Split;
}

} // namespace shatter::fracture
