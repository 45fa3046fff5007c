#include <shatter/plugin/oriented/SelfContacts.h>

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <string>

namespace shatter::oriented {

namespace {

// The largest separation of `other` beyond one of `faces`' planes (its vertices' lowest
// distance above the plane), and that plane's normal; stops at the first beyond `enough`.
PrimitiveSeparation beyondFaces(const geometry::ConvexPolyhedron& faces, const geometry::ConvexPolyhedron& other,
                                double enough) {
    PrimitiveSeparation best{-std::numeric_limits<double>::infinity(), Eigen::Vector3d::UnitZ()};
    for (const geometry::Plane& plane : faces.planes()) {
        double lowest = std::numeric_limits<double>::infinity();
        for (const Eigen::Vector3d& v : other.vertices()) lowest = std::min(lowest, plane.signedDistance(v));
        if (lowest > best.distance) best = {lowest, plane.normal};
        if (best.distance > enough) break;
    }
    return best;
}

// faceSeparation, but any answer beyond `enough` may be any separation beyond it.
PrimitiveSeparation separationUpTo(const geometry::ConvexPolyhedron& a, const geometry::ConvexPolyhedron& b,
                                   double enough) {
    PrimitiveSeparation alongA = beyondFaces(a, b, enough); // b beyond a's face: a is pushed against its normal
    alongA.normal = -alongA.normal;
    if (alongA.distance > enough) return alongA;
    const PrimitiveSeparation alongB = beyondFaces(b, a, enough); // a beyond b's face: pushed along it
    return alongB.distance > alongA.distance ? alongB : alongA;
}

} // namespace

PrimitiveSeparation faceSeparation(const geometry::ConvexPolyhedron& a, const geometry::ConvexPolyhedron& b) {
    return separationUpTo(a, b, std::numeric_limits<double>::infinity());
}

SelfContactCandidates::SelfContactCandidates(double skin) : skin_(skin) {}

bool SelfContactCandidates::covers(const std::vector<geometry::ConvexPolyhedron>& primitives) const {
    if (grown_.size() != primitives.size()) return false;
    // Boxes that all moved by the same d overlap as they did: the list still holds every
    // overlapping pair while each box, moved back by one common d, is inside its grown box.
    // So a body falling or swinging as a whole keeps its list. The feasible d lies between the
    // largest push of a box's top past its grown top and the least room below its bottom.
    Eigen::Array3d least = Eigen::Array3d::Constant(std::numeric_limits<double>::infinity());
    Eigen::Array3d most = -least;
    for (size_t i = 0; i < primitives.size(); ++i) {
        const geometry::Aabb& box = primitives[i].bounds();
        least = least.min(box.min.array() - grown_[i].min.array());
        most = most.max(box.max.array() - grown_[i].max.array());
    }
    if ((most > least).any()) return false;
    // No shift needed (every box inside its own grown box: fl(a − b) ≥ 0 exactly when a ≥ b).
    if ((most <= 0.0).all() && (least >= 0.0).all()) return true;
    const Eigen::Array3d d = 0.5 * (least + most);
    // The test that counts, in the arithmetic of the walk's overlap tests: rounding is
    // monotone, so a.max >= b.min implies a.max − d >= b.min − d as computed, and both
    // grown boxes then overlap too.
    for (size_t i = 0; i < primitives.size(); ++i) {
        const geometry::Aabb& box = primitives[i].bounds();
        if (((box.min.array() - d) < grown_[i].min.array()).any() || ((box.max.array() - d) > grown_[i].max.array()).any())
            return false;
    }
    return true;
}

void SelfContactCandidates::rebuild(const std::vector<geometry::ConvexPolyhedron>& primitives,
                                    const geometry::AabbTree& tree, const ShapeMatchingGroups& groups, double skin) {
    grown_.resize(primitives.size());
    for (size_t i = 0; i < primitives.size(); ++i) grown_[i] = primitives[i].bounds().inflated(skin);
    // The body's tree with grown boxes: growing every box by the same amount keeps the walk's
    // choices (which node to descend first), so the list is in the order a walk over the
    // current boxes gives its pairs, as of this rebuild.
    tree_ = tree;
    tree_.refit(grown_);
    pairs_.clear();
    tree_.selfPairs([&](int a, int b) {
        if (!groups.connected(a, b)) pairs_.emplace_back(a, b);
    });
    groups_ = groups.connectionsVersion();
    ++rebuilds_;
}

void SelfContactCandidates::addContacts(const std::vector<geometry::ConvexPolyhedron>& primitives,
                                        const geometry::AabbTree& tree, const ShapeMatchingGroups& groups,
                                        double reach, double friction, std::vector<ParticleContact>& contacts) {
    if (tree.itemCount() != int(primitives.size()))
        throw std::invalid_argument("SelfContactCandidates: a tree of " + std::to_string(tree.itemCount()) +
                                    " items for " + std::to_string(primitives.size()) + " primitives");
    if (primitives.empty()) return;
    if (groups.connectionsVersion() != groups_ || !covers(primitives)) {
        // A walk over grown boxes costs about twice one over the boxes as they are, so it
        // pays only when its list lasts. After a grown list that lasted one call (the body
        // moves fast), the next walks are over the boxes as they are (a skin of 0: the last
        // step's walk), 1, 2, 4 … up to 16 of them before a grown walk is tried again.
        if (lastGrown_) {
            backoff_ = callsSinceRebuild_ <= 1 ? std::min(2 * backoff_, 16) : 1;
            exactWalksLeft_ = callsSinceRebuild_ <= 1 ? backoff_ : 0;
        }
        lastGrown_ = exactWalksLeft_ == 0;
        if (!lastGrown_) --exactWalksLeft_;
        rebuild(primitives, tree, groups, lastGrown_ ? skin_ : 0.0);
        callsSinceRebuild_ = 0;
    }
    ++callsSinceRebuild_;
    for (const auto& [a, b] : pairs_) {
        const geometry::ConvexPolyhedron& pa = primitives[size_t(a)];
        const geometry::ConvexPolyhedron& pb = primitives[size_t(b)];
        if (!pa.bounds().overlaps(pb.bounds())) continue;
        const PrimitiveSeparation s = separationUpTo(pa, pb, reach);
        if (s.distance > reach) continue;
        ParticleContact c;
        c.particle = a;
        c.otherParticle = b;
        c.normal = s.normal;
        c.distance = s.distance;
        c.friction = friction;
        contacts.push_back(c);
    }
}

} // namespace shatter::oriented
