#include <shatter/bullet_ext/shape/PolyhedronContacts.h>

#include <shatter/bullet_ext/shape/AxisLanes.h>
#include <shatter/bullet_ext/shape/HullLanes.h>

#include <BulletCollision/NarrowPhaseCollision/btPolyhedralContactClipping.h>

#include <algorithm>
#include <bit>
#include <cfloat>
#include <utility>
#include <vector>

namespace shatter {

namespace {

// A hull's extent along an axis, and which vertices give it.
struct Extent {
    btScalar min, max;
    int minAt, maxAt;
};

Extent extentAlong(const btAlignedObjectArray<btVector3>& vertices, const btVector3& axis) {
    Extent e{BT_LARGE_FLOAT, -BT_LARGE_FLOAT, 0, 0};
    for (int k = 0; k < vertices.size(); ++k) {
        const btScalar p = vertices[k].dot(axis);
        if (p < e.min) {
            e.min = p;
            e.minAt = k;
        }
        if (p > e.max) {
            e.max = p;
            e.maxAt = k;
        }
    }
    return e;
}

// The same extent without which vertices give it: what every axis but the last needs.
void spanAlong(const btAlignedObjectArray<btVector3>& vertices, const btVector3& axis, btScalar& min, btScalar& max) {
    min = BT_LARGE_FLOAT;
    max = -BT_LARGE_FLOAT;
    for (int k = 0; k < vertices.size(); ++k) {
        const btScalar p = vertices[k].dot(axis);
        min = p < min ? p : min;
        max = p > max ? p : max;
    }
}

// Bullet's IsAlmostZero: a cross product of (nearly) parallel edges is no axis.
bool almostZero(const btVector3& v) {
    return btFabs(v.x()) <= btScalar(1e-6) && btFabs(v.y()) <= btScalar(1e-6) && btFabs(v.z()) <= btScalar(1e-6);
}

// One separating-axis test between hulls a and b: both in world coordinates, and the axis of
// least overlap so far. World coordinates and Bullet's own arithmetic, operation for
// operation, so that the axis and the points are Bullet's to the bit; only each vertex is
// mapped once, not once per axis.
class AxisSearch {
public:
    // `worldA`, `worldB` and `edgesB` are the caller's buffers (reused: no allocation per pair).
    AxisSearch(const btConvexPolyhedron& a, const btTransform& ta, const btConvexPolyhedron& b, const btTransform& tb,
               btAlignedObjectArray<btVector3>& worldA, btAlignedObjectArray<btVector3>& worldB,
               btAlignedObjectArray<btVector3>& edgesB)
        : a_(a), b_(b), ta_(ta), tb_(tb), worldA_(worldA), worldB_(worldB), edgesB_(edgesB),
          centres_(ta * a.m_localCenter - tb * b.m_localCenter), aFewer_(a.m_vertices.size() <= b.m_vertices.size()),
          whole_(aFewer_ ? worldA : worldB), oneByOne_(aFewer_ ? worldB : worldA),
          inLanes_(a.m_vertices.size() <= VertexLanes::kMaxVertices && b.m_vertices.size() <= VertexLanes::kMaxVertices) {
        if (!inLanes_) {
            place();
            return;
        }
        // Most small pairs (new leaf pairs, each tried once) are apart along a face: that
        // needs only the vertices in lanes; the rest is placed when edges are reached.
        lanesA_ = lanesOf(a, ownA_);
        lanesB_ = lanesOf(b, ownB_);
        for (int k = 0; k < lanesA_->vertexBlocks; ++k) placedA_[k] = placed(ta, lanesA_->vertices[k]);
        for (int k = 0; k < lanesB_->vertexBlocks; ++k) placedB_[k] = placed(tb, lanesB_->vertices[k]);
    }

    // A small hull's vertices and face normals in lanes (HullLanes.h): a's or b's.
    const HullLanes& lanes(bool ofA) const { return ofA ? *lanesA_ : *lanesB_; }

    // The vertices and b's edges in world space (the caller's buffers), as the one-axis code,
    // the edge pairs and the edge-edge point read them; for small hulls, once needed.
    void place() {
        if (placed_) return;
        placed_ = true;
        worldA_.resize(a_.m_vertices.size());
        for (int k = 0; k < a_.m_vertices.size(); ++k) worldA_[k] = ta_ * a_.m_vertices[k];
        worldB_.resize(b_.m_vertices.size());
        for (int k = 0; k < b_.m_vertices.size(); ++k) worldB_[k] = tb_ * b_.m_vertices[k];
        edgesB_.resize(b_.m_uniqueEdges.size());
        for (int k = 0; k < b_.m_uniqueEdges.size(); ++k) edgesB_[k] = tb_.getBasis() * b_.m_uniqueEdges[k];
    }
    const btAlignedObjectArray<btVector3>& edgesB() const { return edgesB_; } // after place()

    // Both hulls have at most VertexLanes::kMaxVertices vertices (a lattice's tets, boxes):
    // every axis is then tried four at a time (inLanes), not by overlaps().
    bool small() const { return inLanes_; }

    int faces() const { return a_.m_faces.size() + b_.m_faces.size(); }
    int axes() const { return faces() + a_.m_uniqueEdges.size() * b_.m_uniqueEdges.size(); }
    const btVector3& centres() const { return centres_; } // b's centre to a's
    btScalar least() const { return least_; }

    // The direction of the axis numbered k (the header's numbering: a's faces, b's faces, a's
    // edges times b's) as the full test computes it, up to sign; (0, 0, 0) for an edge pair
    // too near parallel to give one (Bullet's IsAlmostZero).
    btVector3 axis(int k) {
        const int facesA = a_.m_faces.size();
        if (k < faces()) {
            const btScalar* p = k < facesA ? a_.m_faces[k].m_plane : b_.m_faces[k - facesA].m_plane;
            return (k < facesA ? ta_ : tb_).getBasis() * btVector3(p[0], p[1], p[2]);
        }
        const int e = k - faces();
        place();
        btVector3 cross = edgeA(e / edgesB_.size()).cross(edgesB_[e % edgesB_.size()]);
        return almostZero(cross) ? btVector3(0, 0, 0) : cross.normalize();
    }
    btVector3 edgeA(int i) const { return ta_.getBasis() * a_.m_uniqueEdges[i]; }

    // Whether the unit axis n separates the hulls (the sign of n does not matter).
    bool separates(const btVector3& n) const {
        if (inLanes_) return apart(overlapInLanes(splat(n))[0]);
        btScalar minA, maxA, minB, maxB;
        spanAlong(worldA_, n, minA, maxA);
        spanAlong(worldB_, n, minB, maxB);
        return maxA < minB || maxB < minA;
    }

    // Tries the unit axis n (from the edges ea of a and eb of b, or −1 for a face), reading
    // vertices only until its outcome is known, and settles it: false when it separates the
    // hulls. For hulls that are not small (small ones: firstSeparating).
    bool overlaps(btVector3 n, int ea, int eb) {
        if (centres_.dot(n) < 0) n *= btScalar(-1);
        Partial s;
        if (partlyReached(n, s)) return true;
        const btScalar minA = aFewer_ ? s.low : s.lowRead, maxA = aFewer_ ? s.high : s.highRead;
        const btScalar minB = aFewer_ ? s.lowRead : s.low, maxB = aFewer_ ? s.highRead : s.high;
        const btScalar d0 = maxA - minB, d1 = maxB - minA;
        return settle(n, maxA < minB || maxB < minA, d0 < d1 ? d0 : d1, ea, eb);
    }

    // Small hulls: the four unit axes of `axes` (lanes set in `valid`) tried as overlaps()
    // tries each, in lane order; each lane's axis, turn and projections have the bits the
    // one-axis code computes (AxisLanes.h), and an axis's overlap does not depend on the
    // least so far, so only the settling goes lane by lane. The lane of the first axis that
    // separates the hulls, or −1. Edge pairs: a's edge ea with b's edges firstEb + lane
    // (faces: −1 for both).
    int firstSeparating(const Vector4& axes, int valid, int ea, int firstEb) {
        const Vector4 turned = turnedTowards(axes, centres_);
        const Float4 depth = overlapInLanes(turned);
        // The least overlap is never negative (an overlapping axis's extents give d0, d1 >= 0),
        // so an axis apart whose inner-bound overlap is not positive separates them whatever
        // the axes before it in the block settle (which returning false makes moot).
        const auto apartLanes = depth < Float4{};
        const int firstApart = std::countr_zero(unsigned(valid & ((apartLanes[0] & 1) | (apartLanes[1] & 2) |
                                                                 (apartLanes[2] & 4) | (apartLanes[3] & 8))));
        if (firstApart < 4 &&
            !(innerOverlap(btVector3(turned.x[firstApart], turned.y[firstApart], turned.z[firstApart])) > btScalar(0)))
            return firstApart;
        for (; valid != 0; valid &= valid - 1) {
            const int l = std::countr_zero(unsigned(valid));
            const btVector3 n(turned.x[l], turned.y[l], turned.z[l]);
            if (!settle(n, apart(depth[l]), depth[l], ea, firstEb < 0 ? -1 : firstEb + l)) return l;
        }
        return -1;
    }

    // After every axis: adds Bullet's edge-edge point when an edge pair's axis is the least,
    // and returns the axis turned from b to a.
    btVector3 finish(btDiscreteCollisionDetectorInterface::Result& result) {
        if (edgeA_ >= 0) {
            place();
            addEdgeContact(result);
        }
        return centres_.dot(axis_) < btScalar(0) ? -axis_ : axis_;
    }

private:
    // The turned unit axis n, whose extents are apart or overlap by `depth`: false when it
    // separates the hulls; otherwise it becomes the least if it overlaps less than every
    // earlier axis (a tie keeps the earlier one) and Bullet's inner bound does not skip it.
    bool settle(const btVector3& n, bool apart, btScalar depth, int ea, int eb) {
        // Bullet skips an axis its inner bound rules out before it projects anything.
        if (apart) return cannotMatter(n);
        if (depth < least_ && !cannotMatter(n)) {
            least_ = depth;
            axis_ = n;
            edgeA_ = ea;
            edgeB_ = eb;
        }
        return true;
    }

    // From the overlap min(maxA − minB, maxB − minA) of the whole hulls: whether maxA < minB
    // or maxB < minA. A float difference of finite floats is negative exactly when the first
    // is the smaller (rounding keeps the sign; gradual underflow gives no false zero).
    static bool apart(btScalar overlap) { return overlap < btScalar(0); }

    // Small hulls: the overlap along the four turned unit axes of `axes` (lanes), from every
    // vertex of both.
    Float4 overlapInLanes(const Vector4& axes) const {
        return blockOverlap(axes, placedA_, lanesA_->vertexBlocks, placedB_, lanesB_->vertexBlocks);
    }

    // The lanes h keeps (a group's leaf hull), else `own` filled from h.
    static const HullLanes* lanesOf(const btConvexPolyhedron& h, HullLanes& own) {
        if (const HullLanes* kept = keptLanes(h)) return kept;
        own.assign(h);
        return &own;
    }

    // Extents along an axis from the vertices read so far: the hull projected whole (low,
    // high) and the other (lowRead, highRead). Each difference of extremes only grows as
    // vertices are read (rounding is monotonic).
    struct Partial {
        btScalar low = BT_LARGE_FLOAT, high = -BT_LARGE_FLOAT, lowRead = BT_LARGE_FLOAT, highRead = -BT_LARGE_FLOAT;
        // Both differences reach `least`: the axis can neither separate the hulls (the least
        // is never negative) nor be the least (a tie keeps the earlier axis), whatever the
        // vertices not read would say.
        bool reached(btScalar least) const {
            const btScalar below = high - lowRead, above = highRead - low;
            return (below < above ? below : above) >= least;
        }
    };

    // Reads vertices along the turned axis n into `s` until both differences reach the least
    // (true) or every vertex is read (false: `s` holds both hulls' extents). Extremes do not
    // depend on the order vertices are read in, so they are read where the last axes ended
    // first: most axes of a touching pair end after the whole hull's two old extremes and a
    // vertex or two of the other.
    bool partlyReached(const btVector3& n, Partial& s) {
        for (const int k : {wholeLow_, wholeHigh_}) {
            const btScalar p = whole_[k].dot(n);
            s.low = p < s.low ? p : s.low;
            s.high = p > s.high ? p : s.high;
        }
        int read = 0, k = lastRead_;
        const auto readNext = [&] {
            const btScalar p = oneByOne_[k].dot(n);
            s.lowRead = p < s.lowRead ? p : s.lowRead;
            s.highRead = p > s.highRead ? p : s.highRead;
            ++read;
            if (s.reached(least_)) {
                lastRead_ = k;
                return true;
            }
            k = k + 1 == oneByOne_.size() ? 0 : k + 1;
            return false;
        };
        const int beforeWhole = 3; // reads of the other hull before the whole hull is read
        while (read < oneByOne_.size() && read < beforeWhole)
            if (readNext()) return true;
        for (int w = 0; w < whole_.size(); ++w) {
            const btScalar p = whole_[w].dot(n);
            if (p < s.low) {
                s.low = p;
                wholeLow_ = w;
            }
            if (p > s.high) {
                s.high = p;
                wholeHigh_ = w;
            }
        }
        if (read > 0 && s.reached(least_)) return true;
        while (read < oneByOne_.size())
            if (readNext()) return true;
        return false;
    }

    // Both hulls hold their inner box (m_extents) and inner ball (m_radius) about their
    // centre, so along the unit axis n they overlap by at least the larger of the two radii of
    // each less |centres · n|: where that exceeds the least overlap so far, the axis can
    // neither separate them nor be the least. Bullet skips such axes (TestInternalObjects);
    // the same test in the same arithmetic keeps its float results.
    static btScalar innerRadius(const btConvexPolyhedron& h, const btMatrix3x3& basis, const btVector3& n) {
        const btVector3 &r0 = basis[0], &r1 = basis[1], &r2 = basis[2];
        const btScalar x = r0.x() * n.x() + r1.x() * n.y() + r2.x() * n.z();
        const btScalar y = r0.y() * n.x() + r1.y() * n.y() + r2.y() * n.z();
        const btScalar z = r0.z() * n.x() + r1.z() * n.y() + r2.z() * n.z();
        const btScalar box = (x < 0 ? -h.m_extents.x() : h.m_extents.x()) * x +
                             (y < 0 ? -h.m_extents.y() : h.m_extents.y()) * y +
                             (z < 0 ? -h.m_extents.z() : h.m_extents.z()) * z;
        return box > h.m_radius ? box : h.m_radius;
    }
    btScalar innerOverlap(const btVector3& n) const {
        const btScalar along = centres_.dot(n);
        const btScalar radii = innerRadius(b_, tb_.getBasis(), n) + innerRadius(a_, ta_.getBasis(), n);
        const btScalar d0 = radii + along, d1 = radii - along;
        return d0 < d1 ? d0 : d1;
    }
    bool cannotMatter(const btVector3& n) const { return innerOverlap(n) > least_; }

    // Bullet's edge-edge point: the closest points of the two edges' lines through the
    // witness vertices (where the extents along the axis overlap, the first of equal ones, as
    // Bullet's projection keeps), at their distance as the depth.
    void addEdgeContact(btDiscreteCollisionDetectorInterface::Result& result) const {
        const Extent ofA = extentAlong(worldA_, axis_), ofB = extentAlong(worldB_, axis_);
        const bool aBelow = ofA.max - ofB.min < ofB.max - ofA.min;
        const btVector3& witnessA = worldA_[aBelow ? ofA.maxAt : ofA.minAt];
        const btVector3& witnessB = worldB_[aBelow ? ofB.minAt : ofB.maxAt];
        const btVector3 edgeDirA = edgeA(edgeA_);
        const btVector3& edgeDirB = edgesB_[edgeB_];
        const btVector3 fromA = witnessB - witnessA;
        const btScalar ab = btDot(edgeDirA, edgeDirB), at = btDot(edgeDirA, fromA), bt = btDot(edgeDirB, fromA);
        const btScalar denom = btScalar(1) - ab * ab;
        const btScalar tA = denom == btScalar(0) ? btScalar(0) : (at - bt * ab) / denom;
        const btScalar tB = tA * ab - bt;
        const btVector3 offsetB = edgeDirB * tB;
        btVector3 between = fromA - edgeDirA * tA + offsetB;
        const btScalar length2 = between.length2();
        if (length2 > SIMD_EPSILON) {
            const btScalar length = btSqrt(length2);
            between *= btScalar(1) / length;
            if (between.dot(centres_) < btScalar(0)) between *= btScalar(-1);
            result.addContactPoint(between, witnessB + offsetB, -length);
        }
    }

    const btConvexPolyhedron &a_, &b_;
    const btTransform &ta_, &tb_;
    btAlignedObjectArray<btVector3>&worldA_, &worldB_, &edgesB_;
    const btVector3 centres_;
    // The hull with fewer vertices is projected whole, the other vertex by vertex.
    const bool aFewer_;
    const btAlignedObjectArray<btVector3>&whole_, &oneByOne_;
    // Two small hulls (a lattice's tets, boxes): four axes at once, every vertex projected
    // (placedA_, placedB_: the vertices in world space, four a block), which costs less than
    // the reads vertex by vertex, however early they end.
    const bool inLanes_;
    bool placed_ = false; // place() done
    HullLanes ownA_, ownB_; // a hull's lanes when it keeps none
    const HullLanes *lanesA_ = nullptr, *lanesB_ = nullptr;
    Vector4 placedA_[HullLanes::kMaxVertices / 4], placedB_[HullLanes::kMaxVertices / 4];
    // Where the last axes ended: the whole hull's extreme vertices, the other's deciding one.
    // Neighbouring axes are alike, so these usually decide the next one too.
    int wholeLow_ = 0, wholeHigh_ = 0, lastRead_ = 0;
    btScalar least_ = FLT_MAX;
    btVector3 axis_{0, 0, 0};
    int edgeA_ = -1, edgeB_ = -1;
};

// Vertices of a hull (world coordinates), each in every lane, whose extent along most axes is
// nearly the hull's: every vertex of a hull of up to 10, else those farthest along ±x, ±y and
// ±z (the hull's span) and the 4 nearest `near` (where it meets the other hull). On homer's
// touching pairs these bound 98.5% of the edge axes past the least overlap.
constexpr int kWholeSample = 10;
void sampleVertices(const btAlignedObjectArray<btVector3>& world, const btVector3& near, std::vector<Vector4>& sample) {
    sample.clear();
    const int nearest = 4;
    if (world.size() <= kWholeSample) {
        for (int k = 0; k < world.size(); ++k) sample.push_back(splat(world[k]));
        return;
    }
    int extreme[6] = {0, 0, 0, 0, 0, 0}; // the lowest and highest in x, y, z
    int closest[nearest] = {0, 0, 0, 0};
    btScalar distance2[nearest] = {BT_LARGE_FLOAT, BT_LARGE_FLOAT, BT_LARGE_FLOAT, BT_LARGE_FLOAT};
    for (int k = 0; k < world.size(); ++k) {
        const btVector3& v = world[k];
        for (int c = 0; c < 3; ++c) {
            if (v[c] < world[extreme[2 * c]][c]) extreme[2 * c] = k;
            if (v[c] > world[extreme[2 * c + 1]][c]) extreme[2 * c + 1] = k;
        }
        btScalar d = (v - near).length2();
        int at = k;
        for (int q = 0; q < nearest; ++q) // insertion into the sorted nearest
            if (d < distance2[q]) {
                std::swap(d, distance2[q]);
                std::swap(at, closest[q]);
            }
    }
    const auto add = [&](int k) {
        for (const Vector4& s : sample)
            if (s.x[0] == world[k].x() && s.y[0] == world[k].y() && s.z[0] == world[k].z()) return;
        sample.push_back(splat(world[k]));
    };
    for (const int k : extreme) add(k);
    for (const int k : closest) add(k);
}

// Face f's normal, in its hull's frame.
btVector3 faceNormal(const btConvexPolyhedron& h, int f) {
    const btScalar* p = h.m_faces[f].m_plane;
    return btVector3(p[0], p[1], p[2]);
}

// Vectors first .. first + 3 of `count` (vectorAt(k)) in one block's lanes, zero vectors in the
// spare lanes.
template <class VectorAt>
Vector4 laneBlock(int first, int count, const VectorAt& vectorAt) {
    Vector4 v{};
    for (int l = 0; l < 4 && first + l < count; ++l) {
        const btVector3 u = vectorAt(first + l);
        v.x[l] = u.x();
        v.y[l] = u.y();
        v.z[l] = u.z();
    }
    return v;
}

// The test's axes four at a time (four faces of one hull, or one of a's edges with four of
// b's): lanes whose axis's overlap, bounded from below by a sample of each hull's vertices
// (AxisLanes.h: the bits the one-axis code computes), reaches the least overlap so far. Such
// an axis can neither separate the hulls nor be the least, so the test need not try it.
class AxisBounds {
public:
    AxisBounds(const btConvexPolyhedron& a, const btTransform& ta, const btConvexPolyhedron& b, const btTransform& tb,
               const btAlignedObjectArray<btVector3>& worldA, const btAlignedObjectArray<btVector3>& worldB,
               const btAlignedObjectArray<btVector3>& edgesB, const btVector3& centres)
        : ta_(ta), tb_(tb), centres_(centres), on_(std::max(worldA.size(), worldB.size()) > kWholeSample) {
        // Two hulls of at most 8 vertices (a lattice's tets, boxes) never get here: they try
        // every axis four at a time (smallLeastOverlapAxis). Up to kWholeSample vertices the
        // one-axis code reads few vertices per axis and the bounds' setup costs more than it
        // saves (the table's leaf pairs: +44% instructions); there the bounds are off.
        if (!on_) return;
        thread_local std::vector<Vector4> sampleA, sampleB, facesA, facesB, edgeBlocks; // reused: no allocation per pair
        sampleVertices(worldA, centreOf(worldB), sampleA);
        sampleVertices(worldB, centreOf(worldA), sampleB);
        const auto inBlocks = [](int count, const auto& vectorAt, std::vector<Vector4>& blocks) {
            blocks.clear();
            for (int first = 0; first < count; first += 4) blocks.push_back(laneBlock(first, count, vectorAt));
        };
        inBlocks(a.m_faces.size(), [&](int f) { return faceNormal(a, f); }, facesA);
        inBlocks(b.m_faces.size(), [&](int f) { return faceNormal(b, f); }, facesB);
        inBlocks(edgesB.size(), [&](int j) { return edgesB[j]; }, edgeBlocks);
        a_ = {sampleA.data(), int(sampleA.size())};
        b_ = {sampleB.data(), int(sampleB.size())};
        facesA_ = facesA.data();
        facesB_ = facesB.data();
        edgeBlocks_ = edgeBlocks.data();
    }

    // Bit l set: the axis of face first + l of a (ofA) or b cannot matter while the least
    // overlap is at most `least` (first a multiple of 4). Spare lanes (zero normals, beyond
    // the hull's faces) say nothing: the caller masks them (lanesFrom).
    int facesCannotMatter(bool ofA, int first, btScalar least) const {
        if (!on_) return 0;
        const Vector4& normals = (ofA ? facesA_ : facesB_)[first / 4];
        return reached(rotated((ofA ? ta_ : tb_).getBasis(), normals), least);
    }

    // Bit l set: the axis of a's edge `edgeA` (in every lane) and b's edge first + l cannot
    // matter while the least overlap is at most `least`. Spare lanes as above.
    int edgesCannotMatter(const Vector4& edgeA, int first, btScalar least) const {
        if (!on_) return 0;
        return reached(normalized(cross(edgeA, edgeBlocks_[first / 4])), least);
    }

private:
    int reached(const Vector4& axes, btScalar least) const {
        const auto reached = overlapBelow(turnedTowards(axes, centres_), a_, b_) >= least;
        return (reached[0] & 1) | (reached[1] & 2) | (reached[2] & 4) | (reached[3] & 8);
    }

    static btVector3 centreOf(const btAlignedObjectArray<btVector3>& world) {
        btVector3 sum(0, 0, 0);
        for (int k = 0; k < world.size(); ++k) sum += world[k];
        return sum / btScalar(world.size());
    }

    const btTransform &ta_, &tb_;
    btVector3 centres_;
    bool on_; // a hull has more vertices than a whole sample
    Sample a_{}, b_{};
    const Vector4 *facesA_ = nullptr, *facesB_ = nullptr, *edgeBlocks_ = nullptr;
};

// The lanes of a block of four from `first` that hold one of `count` axes.
int lanesFrom(int first, int count) { return count - first < 4 ? (1 << (count - first)) - 1 : 15; }

// Lanes whose vector is no axis (Bullet's IsAlmostZero, lane by lane).
int almostZeroLanes(const Vector4& v) {
    const Float4 limit = Float4{} + btScalar(1e-6);
    const auto within = [&](const Float4& c) { return c <= limit && c >= -limit; }; // btFabs(c) <= limit
    const auto zero = within(v.x) & within(v.y) & within(v.z);
    return (zero[0] & 1) | (zero[1] & 2) | (zero[2] & 4) | (zero[3] & 8);
}

// leastOverlapAxis for two small hulls: the same axes in the same order, four at a time
// (AxisSearch::firstSeparating).
bool smallLeastOverlapAxis(AxisSearch& search, const btConvexPolyhedron& a, const btTransform& ta,
                           const btConvexPolyhedron& b, const btTransform& tb, btVector3& normal,
                           btDiscreteCollisionDetectorInterface::Result& result, int* separating) {
    // Axes from k + lane: false (and the hint set) when one separates the hulls.
    const auto tryBlock = [&](int k, const Vector4& axes, int valid, int ea, int firstEb) {
        const int l = search.firstSeparating(axes, valid, ea, firstEb);
        if (l < 0) return true;
        if (separating) *separating = k + l;
        return false;
    };
    for (const bool ofA : {true, false}) {
        const btConvexPolyhedron& h = ofA ? a : b;
        const HullLanes& lanes = search.lanes(ofA);
        const btMatrix3x3& basis = (ofA ? ta : tb).getBasis();
        const int faces = h.m_faces.size(), offset = ofA ? 0 : a.m_faces.size();
        const auto normalAt = [&h](int f) { return faceNormal(h, f); };
        for (int first = 0; first < faces; first += 4) {
            const Vector4 normals = lanes.faceBlocks > 0 ? lanes.faceNormals[first / 4] : laneBlock(first, faces, normalAt);
            if (!tryBlock(offset + first, rotated(basis, normals), lanesFrom(first, faces), -1, -1)) return false;
        }
    }
    search.place();
    const btAlignedObjectArray<btVector3>& edgesB = search.edgesB();
    const int edgesOfB = edgesB.size();
    thread_local std::vector<Vector4> edgeBlocks; // reused: no allocation per pair
    edgeBlocks.clear();
    for (int first = 0; first < edgesOfB; first += 4)
        edgeBlocks.push_back(laneBlock(first, edgesOfB, [&](int j) { return edgesB[j]; }));
    for (int i = 0; i < a.m_uniqueEdges.size(); ++i) {
        const Vector4 edge = splat(search.edgeA(i));
        for (int first = 0; first < edgesOfB; first += 4) {
            const Vector4 crosses = cross(edge, edgeBlocks[size_t(first / 4)]);
            const int valid = lanesFrom(first, edgesOfB) & ~almostZeroLanes(crosses);
            if (valid != 0 && !tryBlock(search.faces() + i * edgesOfB + first, normalized(crosses), valid, i, first))
                return false;
        }
    }
    normal = search.finish(result);
    return true;
}

} // namespace

bool leastOverlapAxis(const btConvexPolyhedron& a, const btTransform& ta, const btConvexPolyhedron& b,
                      const btTransform& tb, btVector3& normal, btDiscreteCollisionDetectorInterface::Result& result,
                      int* separating) {
    // A hull without vertices has no point to touch with (its spans would be empty).
    if (a.m_vertices.size() == 0 || b.m_vertices.size() == 0) return false;
    thread_local btAlignedObjectArray<btVector3> worldA, worldB, edgesB;
    AxisSearch search(a, ta, b, tb, worldA, worldB, edgesB);
    if (separating && *separating >= 0 && *separating < search.axes() && search.separates(search.axis(*separating)))
        return false;
    // Any axis in the header's numbering: false (and the hint set) when it separates them.
    const auto tryAxis = [&](int k, const btVector3& n, int ea, int eb) {
        if (search.overlaps(n, ea, eb)) return true;
        if (separating) *separating = k;
        return false;
    };
    if (search.small()) return smallLeastOverlapAxis(search, a, ta, b, tb, normal, result, separating);
    // Four axes at a time, each block's bounds taken before any of its axes is tried: the
    // least only shrinks, so a bound that reaches it then still does when the axis's turn
    // comes; only the others are tried, in order. Most of a fragment's many faces and ~1,700
    // edge pairs, when its hull touches a primitive, are far from the least overlap.
    const AxisBounds bounds(a, ta, b, tb, worldA, worldB, edgesB, search.centres());
    for (const bool ofA : {true, false}) {
        const int faces = (ofA ? a : b).m_faces.size(), offset = ofA ? 0 : a.m_faces.size();
        for (int first = 0; first < faces; first += 4)
            for (int tried = lanesFrom(first, faces) & ~bounds.facesCannotMatter(ofA, first, search.least());
                 tried != 0; tried &= tried - 1) {
                const int k = offset + first + std::countr_zero(unsigned(tried));
                if (!tryAxis(k, search.axis(k), -1, -1)) return false;
            }
    }
    for (int i = 0; i < a.m_uniqueEdges.size(); ++i) {
        const btVector3 edge = search.edgeA(i);
        const Vector4 edgeLanes = splat(edge);
        for (int first = 0; first < edgesB.size(); first += 4) {
            for (int tried = lanesFrom(first, edgesB.size()) & ~bounds.edgesCannotMatter(edgeLanes, first, search.least());
                 tried != 0; tried &= tried - 1) {
                const int j = first + std::countr_zero(unsigned(tried));
                btVector3 cross = edge.cross(edgesB[j]);
                if (almostZero(cross)) continue;
                if (!tryAxis(search.faces() + i * edgesB.size() + j, cross.normalize(), i, j)) return false;
            }
        }
    }
    normal = search.finish(result);
    return true;
}

bool polyhedronContacts(const btConvexPolyhedron& a, const btTransform& ta, const btConvexPolyhedron& b,
                        const btTransform& tb, btScalar threshold, btDiscreteCollisionDetectorInterface::Result& result,
                        int* separating) {
    btVector3 normal;
    if (!leastOverlapAxis(a, ta, b, tb, normal, result, separating)) return false;
    thread_local btVertexArray clip1, clip2; // reused: no allocation per pair
    clip1.resize(0);
    btPolyhedralContactClipping::clipHullAgainstHull(normal, a, b, ta, tb, btScalar(-1e30) - threshold, threshold, clip1,
                                                     clip2, result);
    return true;
}

bool hullBoxContact(const btConvexPolyhedron& hull, const btTransform& hullPose, btScalar hullMargin,
                    const btVector3& half, const btTransform& boxPose, btScalar threshold, BoxContact& contact) {
    // Everything in the box's frame. Reused buffers: no allocation per pair.
    thread_local btAlignedObjectArray<btVector3> vertices, edges;
    const btTransform toBox = boxPose.inverseTimes(hullPose);
    const btMatrix3x3& turn = toBox.getBasis();
    vertices.resize(hull.m_vertices.size());
    for (int k = 0; k < hull.m_vertices.size(); ++k) vertices[k] = toBox * hull.m_vertices[k];
    edges.resize(hull.m_uniqueEdges.size());
    for (int k = 0; k < hull.m_uniqueEdges.size(); ++k) edges[k] = turn * hull.m_uniqueEdges[k];
    const btVector3 centre = toBox * hull.m_localCenter;

    // The gap along n, turned to point from the box towards the hull: the hull's nearest
    // vertex beyond the box's farthest corner.
    enum class Kind { BoxFace, HullFace, Edges };
    btScalar best = -BT_LARGE_FLOAT;
    btVector3 axis(0, 1, 0);
    Kind kind = Kind::BoxFace;
    int boxAxis = 0;
    btScalar nearest = 0, farthest = 0; // along the axis: the hull's nearest vertex, the box's farthest corner
    // Any axis's gap is at most the distance: one beyond the margin and threshold ends the test.
    const btScalar reach = hullMargin + threshold;
    const auto apartAlong = [&](btVector3 n, Kind k, int b) {
        btScalar toward = centre.dot(n);
        if (toward < 0) {
            n = -n;
            toward = -toward; // exactly centre.dot(n): negation is exact
        }
        const btScalar corner = btFabs(n.x()) * half.x() + btFabs(n.y()) * half.y() + btFabs(n.z()) * half.z();
        // The centre is inside the hull by its inner radius (m_radius, about m_localCenter), far
        // more than rounding: every vertex is nearer than the centre along n, so this axis's
        // gap is below the centre's, and an axis whose centre gap does not beat the best gap
        // so far can neither be chosen nor end the test (best ≤ reach). Skipping its vertices
        // changes no result; most axes of a primitive lying on a box are such (its sides).
        if (toward - corner <= best) return false;
        btScalar least = BT_LARGE_FLOAT;
        for (int v = 0; v < vertices.size(); ++v) least = btMin(least, vertices[v].dot(n));
        const btScalar gap = least - corner;
        if (gap > best) {
            best = gap;
            axis = n;
            kind = k;
            boxAxis = b;
            nearest = least;
            farthest = corner;
        }
        return gap > reach;
    };
    for (int i = 0; i < 3; ++i) {
        btVector3 n(0, 0, 0);
        n[i] = 1;
        if (apartAlong(n, Kind::BoxFace, i)) return false;
    }
    for (int f = 0; f < hull.m_faces.size(); ++f) {
        const btScalar* p = hull.m_faces[f].m_plane;
        if (apartAlong(turn * btVector3(p[0], p[1], p[2]), Kind::HullFace, -1)) return false;
    }
    for (int e = 0; e < edges.size(); ++e)
        for (int i = 0; i < 3; ++i) {
            btVector3 unit(0, 0, 0);
            unit[i] = 1;
            const btVector3 cross = edges[e].cross(unit);
            if (almostZero(cross)) continue;
            if (apartAlong(cross.normalized(), Kind::Edges, i)) return false;
        }
    const btScalar distance = best - hullMargin;

    // Features deepest along the axis, within a twentieth of the hull's inner radius (a face
    // lying flat), or a thousandth of the box's size (its corners).
    const btScalar tolerance = btScalar(0.05) * hull.m_radius;
    const btScalar boxTolerance = btScalar(1e-3) * half.length();
    btVector3 onBox(0, 0, 0);
    if (kind == Kind::HullFace) {
        // A box corner, edge or face in the hull's face: the middle of the hull's face
        // (its deepest vertices) put on the box's deepest feature, the corners deepest along
        // the axis: each coordinate they share is taken, the others are clamped to the box.
        btVector3 middle(0, 0, 0);
        int count = 0;
        for (int v = 0; v < vertices.size(); ++v)
            if (vertices[v].dot(axis) <= nearest + tolerance) {
                middle += vertices[v];
                ++count;
            }
        middle /= btScalar(count);
        int low = 0, high = 0; // per coordinate (bit i): a deepest corner has −h there, +h there
        for (int k = 0; k < 8; ++k) {
            const btVector3 corner(k & 1 ? half.x() : -half.x(), k & 2 ? half.y() : -half.y(), k & 4 ? half.z() : -half.z());
            if (corner.dot(axis) < farthest - boxTolerance) continue;
            high |= k;
            low |= ~k & 7;
        }
        for (int i = 0; i < 3; ++i) {
            const bool atHigh = (high >> i) & 1, atLow = (low >> i) & 1;
            onBox[i] = atHigh && atLow ? btClamped(middle[i], -half[i], half[i]) : atHigh ? half[i] : -half[i];
        }
    } else {
        btVector3 sum(0, 0, 0);
        int count = 0;
        int first = -1, second = -1;
        for (int v = 0; v < vertices.size(); ++v)
            if (vertices[v].dot(axis) <= nearest + tolerance) {
                sum += vertices[v];
                ++count;
                (first < 0 ? first : second) = v;
            }
        btVector3 onHull = sum / btScalar(count);
        if (kind == Kind::Edges && count == 2) {
            // The point of the hull's edge nearest the box's edge along boxAxis (through the
            // box's corner farthest along the axis).
            btVector3 corner(axis.x() < 0 ? -half.x() : half.x(), axis.y() < 0 ? -half.y() : half.y(),
                             axis.z() < 0 ? -half.z() : half.z());
            corner[boxAxis] = 0;
            const btVector3 d = vertices[second] - vertices[first];
            btVector3 unit(0, 0, 0);
            unit[boxAxis] = 1;
            // Closest point of the segment to the line: minimise |(p − corner) − ((p − corner)·u)u|.
            btVector3 across = d - unit * d.dot(unit);
            const btVector3 start = (vertices[first] - corner) - unit * (vertices[first] - corner).dot(unit);
            const btScalar length2 = across.length2();
            const btScalar t = length2 > SIMD_EPSILON ? btClamped(-start.dot(across) / length2, btScalar(0), btScalar(1)) : btScalar(0.5);
            onHull = vertices[first] + d * t;
        }
        // On the box's surface: the box's extent along the axis is the hull's least less the gap.
        onBox = onHull - axis * (onHull.dot(axis) - (nearest - best));
    }
    contact.normal = boxPose.getBasis() * axis;
    contact.onBox = boxPose * onBox;
    contact.distance = distance;
    return true;
}

btConvexPolyhedron boxPolyhedron(const btVector3& h) {
    btConvexPolyhedron box;
    for (int k = 0; k < 8; ++k)
        box.m_vertices.push_back(btVector3(k & 1 ? h.x() : -h.x(), k & 2 ? h.y() : -h.y(), k & 4 ? h.z() : -h.z()));
    // Face with outward normal ±axis: tangents u, w with u × w = the normal give the
    // counter-clockwise corners (-u-w, +u-w, +u+w, -u+w) seen from outside.
    const auto corner = [](int axis, int sign, int u, int su, int w, int sw) {
        int k = 0;
        if (sign > 0) k |= 1 << axis;
        if (su > 0) k |= 1 << u;
        if (sw > 0) k |= 1 << w;
        return k;
    };
    const int tangents[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 2, 0}, {1, 0, 2}, {2, 0, 1}, {2, 1, 0}}; // axis, u, w
    for (int f = 0; f < 6; ++f) {
        const int axis = tangents[f][0], u = tangents[f][1], w = tangents[f][2];
        const int sign = f % 2 == 0 ? 1 : -1;
        btFace face;
        for (const auto& [su, sw] : {std::pair{-1, -1}, std::pair{1, -1}, std::pair{1, 1}, std::pair{-1, 1}})
            face.m_indices.push_back(corner(axis, sign, u, su, w, sw));
        btVector3 n(0, 0, 0);
        n[axis] = btScalar(sign);
        face.m_plane[0] = n.x();
        face.m_plane[1] = n.y();
        face.m_plane[2] = n.z();
        face.m_plane[3] = -h[axis];
        box.m_faces.push_back(face);
    }
    box.m_uniqueEdges.push_back(btVector3(1, 0, 0));
    box.m_uniqueEdges.push_back(btVector3(0, 1, 0));
    box.m_uniqueEdges.push_back(btVector3(0, 0, 1));
    box.initialize();
    return box;
}

} // namespace shatter
