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
    int* mapDown = mapBelow_.data();
    int* mapUp = kAbove ? mapAbove_.data() : nullptr;
    // The crossed edges, found in the same pass (a pass of their own over every face slot
    // cost as much as writing a part): room for one per slot, counted in a local (crossings_
    // only grows). Per vertex, its last crossing to a higher index, the crossings from it
    // chained by Crossing::next: an edge's second face finds its crossing in a chain of one or
    // two. Each crossed edge is met twice (once by each of its faces): the first makes it, so
    // the crossings are numbered in face-slot order.
    if (crossings_.size() < slots) crossings_.resize(slots);
    Crossing* made = crossings_.data();
    int madeCount = 0;
    lastFrom_.assign(size_t(count), -1);
    int* lastFrom = lastFrom_.data();
    const double* distance = distance_.data();
    const Eigen::Vector3d* position = solid.positions.data();
    auto crossing = [&](int a, int b) {
        if (b < a) std::swap(a, b);
        int c = lastFrom[a];
        while (c >= 0 && made[c].b != b) c = made[c].next;
        if (c < 0) {
            // Always from the lower index: both faces of the edge, and both parts, get the same bits.
            const double t = distance[a] / (distance[a] - distance[b]);
            const Eigen::Vector3d& pa = position[a];
            newPositions_.push_back(pa + t * (position[b] - pa));
            c = madeCount++;
            made[c] = {b, lastFrom[a]};
            lastFrom[a] = c;
            mapDown[count + c] = -1;
            if constexpr (kAbove) mapUp[count + c] = -1;
        }
        return c;
    };
    const signed char* side = side_.data();
    const int* vertices = solid.faceVertices.data();
    const int faceCount = solid.faceCount();
    for (int f = 0; f < faceCount; ++f) {
        const int begin = solid.faceStart[size_t(f)], end = solid.faceStart[size_t(f) + 1];
        down.beginFace();
        if constexpr (kAbove) up.beginFace();
        // Slot k: its vertex a, then the crossing on the edge from a to the next vertex b (the
        // first one after the last slot); the sides carried from slot to slot in registers.
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
                const int c = crossing(a, b);
                down.keep(count + c);
                if constexpr (kAbove) up.keep(count + c);
            }
            a = b;
            sa = sb;
        }
        down.endFace(solid.kinds[size_t(f)]);
        if constexpr (kAbove) up.endFace(solid.kinds[size_t(f)]);
    }
    down.finish();
    if constexpr (kAbove) up.finish();
}

bool SolidSplitter::chainCap() {
    cap_.clear();
    if (capEdges_.size() < 3) return false;
    auto next = [&](int from) {
        int to = -1;
        for (const auto& [a, b] : capEdges_)
            if (a == from) {
                if (to >= 0) return -1; // two ways on: not a simple loop
                to = b;
            }
        return to;
    };
    const int start = capEdges_.front().first;
    int v = start;
    do {
        cap_.push_back(v);
        v = next(v);
        if (v < 0 || cap_.size() > capEdges_.size()) return false;
    } while (v != start);
    return cap_.size() == capEdges_.size();
}

SolidSplitter::Outcome SolidSplitter::split(const Solid& solid, const Eigen::Vector3d& n, double d, double tolerance,
                                            NewVertexIds& ids, Solid& below, Solid* above) {
    const int count = int(solid.positions.size());
    distance_.resize(size_t(count));
    side_.resize(size_t(count));
    bool anyBelow = false, anyAbove = false;
    // Through locals: a store to side_ (a char) may alias anything, so the normal and every
    // vector's members were reloaded at each vertex (~30 instructions, 37k vertices a break).
    const Eigen::Vector3d normal = n;
    const Eigen::Vector3d* position = solid.positions.data();
    double* distance = distance_.data();
    signed char* side = side_.data();
    for (int i = 0; i < count; ++i) {
        const double s = normal.dot(position[i]) - d;
        distance[i] = s;
        side[i] = s > tolerance ? 1 : (s < -tolerance ? -1 : 0);
        anyBelow |= side[i] < 0;
        anyAbove |= side[i] > 0;
    }
    if (!anyAbove) return Outcome::Below;
    if (!anyBelow) return Outcome::Above;

    // Both parts in one pass over the faces (each part's vertices and faces come out in the
    // order a pass of its own gave them). The part above is written even when the cut face
    // below does not close and neither part is used.
    if (above) writeParts<true>(solid, below, above);
    else writeParts<false>(solid, below, nullptr);
    // The new vertices' ids, asked for in the order the crossings were made (that order numbers
    // them), then written where each part has the crossing.
    const int* mapDown = mapBelow_.data();
    const int* mapUp = above ? mapAbove_.data() : nullptr;
    for (size_t c = 0; c < newPositions_.size(); ++c) {
        const int id = ids.idAt(newPositions_[c]);
        if (const int i = mapDown[size_t(count) + c]; i >= 0) below.ids[size_t(i)] = id;
        if (mapUp)
            if (const int i = mapUp[size_t(count) + c]; i >= 0) above->ids[size_t(i)] = id;
    }
    if (!chainCap()) {
        // A cut face that does not close (round-off on a nearly degenerate solid): keep the
        // solid whole on the side holding most of it rather than make a broken piece.
        double downward = 0.0, upward = 0.0;
        for (double s : distance_) (s < 0.0 ? downward : upward) += std::abs(s);
        return downward >= upward ? Outcome::Below : Outcome::Above;
    }
    below.faceVertices.insert(below.faceVertices.end(), cap_.begin(), cap_.end());
    below.addFace(FaceKind::Crack);
    if (!above) return Outcome::Split;

    // The part above gets the same cut face reversed, from the same first vertex, so both
    // parts triangulate it alike and their volumes add up to the solid's.
    auto aboveIndex = [&](int belowIndex) { return mapAbove_[size_t(sourceBelow_[size_t(belowIndex)])]; };
    above->faceVertices.push_back(aboveIndex(cap_.front()));
    for (size_t k = cap_.size() - 1; k >= 1; --k) above->faceVertices.push_back(aboveIndex(cap_[k]));
    above->addFace(FaceKind::Crack);
    return Outcome::Split;
}

} // namespace shatter::fracture
