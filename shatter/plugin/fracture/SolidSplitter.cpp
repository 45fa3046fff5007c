#include <shatter/plugin/fracture/SolidSplitter.h>

#include <algorithm>
#include <cmath>

namespace shatter::fracture {

void SolidSplitter::findCrossings(const Solid& solid) {
    crossings_.clear();
    newPositions_.clear();
    edgeCrossing_.resize(solid.faceVertices.size());
    const signed char* side = side_.data();
    const int* vertices = solid.faceVertices.data();
    for (int f = 0; f < solid.faceCount(); ++f) {
        const int begin = solid.faceStart[size_t(f)], end = solid.faceStart[size_t(f) + 1];
        for (int k = begin; k < end; ++k) {
            int a = vertices[k], b = vertices[k + 1 < end ? k + 1 : begin];
            edgeCrossing_[size_t(k)] = -1;
            if (side[a] * side[b] >= 0) continue;
            if (b < a) std::swap(a, b);
            // Each crossed edge is met twice (once by each of its faces): the first makes it.
            int c = 0;
            while (c < int(crossings_.size()) && (crossings_[size_t(c)].a != a || crossings_[size_t(c)].b != b)) ++c;
            if (c == int(crossings_.size())) {
                // Always from the lower index: both faces of the edge, and both parts, get the same bits.
                const double t = distance_[size_t(a)] / (distance_[size_t(a)] - distance_[size_t(b)]);
                const Eigen::Vector3d& pa = solid.positions[size_t(a)];
                newPositions_.push_back(pa + t * (solid.positions[size_t(b)] - pa));
                crossings_.push_back({a, b});
            }
            edgeCrossing_[size_t(k)] = c;
        }
    }
}

void SolidSplitter::writePart(const Solid& solid, int keepSide, Solid& out, std::vector<int>& map, bool collectCap) {
    const int count = int(solid.positions.size());
    const size_t sources = size_t(count) + newPositions_.size();
    map.assign(sources, -1);
    const bool below = keepSide < 0;
    if (below) sourceBelow_.clear();
    capEdges_.clear();
    // Written through pointers into room for the most the part can hold (every vertex source;
    // per face its vertices and a crossing per edge), then cut to what it holds. Not cleared
    // first: every entry kept is written here, and a scratch solid resized from its last size
    // (not from empty) zeroes only what it grows by.
    out.faceStart.assign(1, 0);
    out.kinds.clear();
    out.positions.resize(sources);
    out.ids.resize(sources);
    out.faceVertices.resize(2 * solid.faceVertices.size());
    Eigen::Vector3d* positions = out.positions.data();
    int* ids = out.ids.data();
    int* faceVertices = out.faceVertices.data();
    int vertexCount = 0, slot = 0;
    // The part's index of a vertex source (old vertex, then count + crossing), added on first use.
    auto indexOf = [&](int source) {
        int& index = map[size_t(source)];
        if (index < 0) {
            index = vertexCount++;
            if (source < count) {
                positions[index] = solid.positions[size_t(source)];
                ids[index] = solid.ids[size_t(source)];
            } else {
                positions[index] = newPositions_[size_t(source - count)];
                ids[index] = newIds_[size_t(source - count)];
            }
            if (below) sourceBelow_.push_back(source);
        }
        return index;
    };
    const signed char* side = side_.data();
    const int* vertices = solid.faceVertices.data();
    const int* crossingAt = edgeCrossing_.data();
    for (int f = 0; f < solid.faceCount(); ++f) {
        const int begin = solid.faceStart[size_t(f)], end = solid.faceStart[size_t(f) + 1];
        const int start = slot;
        int first = -1, last = -1;
        bool skipped = false, skippedBeforeFirst = false;
        // An edge between two kept vertices with dropped ones between them lies on the plane:
        // the cut face has it the other way round.
        auto keep = [&](int source) {
            const int index = indexOf(source);
            faceVertices[slot++] = index;
            if (collectCap && skipped && last >= 0 && last != index) capEdges_.emplace_back(index, last);
            if (first < 0) {
                first = index;
                skippedBeforeFirst = skipped;
            }
            last = index;
            skipped = false;
        };
        for (int k = begin; k < end; ++k) {
            const int a = vertices[k];
            if (side[a] * keepSide >= 0) keep(a);
            else skipped = true;
            if (crossingAt[k] >= 0) keep(count + crossingAt[k]);
        }
        if (collectCap && (skipped || skippedBeforeFirst) && first >= 0 && last != first)
            capEdges_.emplace_back(first, last);
        if (slot - start >= 3) { // Solid::addFace, with the face's end known here
            out.faceStart.push_back(slot);
            out.kinds.push_back(solid.kinds[size_t(f)]);
        } else {
            slot = start; // touches the plane in a point or an edge only
        }
    }
    out.positions.resize(size_t(vertexCount));
    out.ids.resize(size_t(vertexCount));
    out.faceVertices.resize(size_t(slot));
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
    for (int i = 0; i < count; ++i) {
        const double s = n.dot(solid.positions[size_t(i)]) - d;
        distance_[size_t(i)] = s;
        side_[size_t(i)] = s > tolerance ? 1 : (s < -tolerance ? -1 : 0);
        anyBelow |= side_[size_t(i)] < 0;
        anyAbove |= side_[size_t(i)] > 0;
    }
    if (!anyAbove) return Outcome::Below;
    if (!anyBelow) return Outcome::Above;

    findCrossings(solid);
    newIds_.clear();
    for (const auto& p : newPositions_) newIds_.push_back(ids.idAt(p));

    writePart(solid, -1, below, mapBelow_, true);
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
    writePart(solid, 1, *above, mapAbove_, false);
    auto aboveIndex = [&](int belowIndex) { return mapAbove_[size_t(sourceBelow_[size_t(belowIndex)])]; };
    above->faceVertices.push_back(aboveIndex(cap_.front()));
    for (size_t k = cap_.size() - 1; k >= 1; --k) above->faceVertices.push_back(aboveIndex(cap_[k]));
    above->addFace(FaceKind::Crack);
    return Outcome::Split;
}

} // namespace shatter::fracture
