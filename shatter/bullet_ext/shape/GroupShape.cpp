#include <shatter/bullet_ext/shape/GroupShape.h>

#include <shatter/bullet_ext/Convert.h>
#include <shatter/bullet_ext/shape/HullLanes.h>
#include <shatter/plugin/geometry/HoleFilling.h>
#include <shatter/plugin/geometry/PolyhedronPrefetch.h>

#include <BulletCollision/CollisionShapes/btConvexPolyhedron.h>
#include <BulletCollision/CollisionShapes/btTriangleCallback.h>
#include <BulletCollision/NarrowPhaseCollision/btPersistentManifold.h>
#include <LinearMath/btAabbUtil2.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <iostream>
#include <limits>
#include <string>

namespace shatter {

namespace {

// Whether the direction `e` is `v` or −v to 1e-6 in every coordinate: Bullet's test
// (lpNorm<Infinity> of e ∓ v below 1e-6), stopping at the first coordinate that differs.
bool sameAxis(const Eigen::Vector3d& e, const btVector3& v) {
    const double x = double(v.x()), y = double(v.y()), z = double(v.z());
    return (std::abs(e.x() - x) < 1e-6 && std::abs(e.y() - y) < 1e-6 && std::abs(e.z() - z) < 1e-6) ||
           (std::abs(e.x() + x) < 1e-6 && std::abs(e.y() + y) < 1e-6 && std::abs(e.z() + z) < 1e-6);
}

// Edge directions of the polyhedron, each once up to sign: the edge-edge axes of Bullet's
// separating-axis test. Not shared with the shard hull's (ConvexHullOfPoints.cpp), on purpose:
// that one must give Bullet's own features bit for bit (float vertices from Bullet's hull
// computer, Bullet's edge order and sign), this one takes a primitive's exact faces in double.
void addUniqueEdges(const geometry::ConvexPolyhedron& p, btConvexPolyhedron& poly) {
    // A closed polyhedron meets each edge twice, the second time the other way round: its
    // direction is then exactly the negated first one, known already, so it is skipped
    // (the same edges in the same order, for half the normalisations and comparisons).
    constexpr int kRemembered = 64;
    std::array<std::pair<int, int>, kRemembered> met;
    int metCount = 0;
    int halfEdges = 0;
    for (const auto& face : p.faces()) halfEdges += int(face.size());
    poly.m_uniqueEdges.reserve(poly.m_uniqueEdges.size() + halfEdges / 2); // one allocation, not one per doubling
    for (const auto& face : p.faces())
        for (size_t k = 0; k < face.size(); ++k) {
            const int a = face[k], b = face[(k + 1) % face.size()];
            if (std::find(met.begin(), met.begin() + metCount, std::pair(b, a)) != met.begin() + metCount) continue;
            if (metCount < kRemembered) met[size_t(metCount++)] = {a, b};
            const Eigen::Vector3d e = (p.vertices()[b] - p.vertices()[a]).normalized();
            bool known = false;
            for (int u = 0; u < poly.m_uniqueEdges.size() && !known; ++u) known = sameAxis(e, poly.m_uniqueEdges[u]);
            if (!known) poly.m_uniqueEdges.push_back(toBullet(e));
        }
}

// The radius of the inner sphere about the centroid `c` (the distance to the nearest face).
btScalar innerRadius(const geometry::ConvexPolyhedron& p, const Eigen::Vector3d& c) {
    double radius = std::numeric_limits<double>::infinity();
    for (const auto& plane : p.planes()) radius = std::min(radius, plane.offset - plane.normal.dot(c));
    return btScalar(std::max(radius, 0.0));
}

// The "internal objects" Bullet's separating-axis test uses to skip axes: a sphere and a box
// about an interior point that lie inside the polyhedron. Bullet's initialize() searches for
// the box with up to 2048 containment tests (75 µs per primitive); here the bounding box,
// scaled about the centroid until it fits behind every face, is found in one pass. Not shared
// with the shard hull's inner box (ConvexHullOfPoints.cpp), which reproduces Bullet's search
// (cube, stretched, widened) about Bullet's centre, for Bullet's features to the bit.
void setInternalObjects(const geometry::ConvexPolyhedron& p, btConvexPolyhedron& poly) {
    const Eigen::Vector3d c = p.massProperties(1.0).centerOfMass;
    const Eigen::Vector3d half = 0.5 * p.bounds().extent();
    double scale = 1.0;
    for (const auto& plane : p.planes()) {
        const double inside = plane.offset - plane.normal.dot(c); // > 0: c is interior
        const double reach = plane.normal.cwiseAbs().dot(half);
        if (reach > 0) scale = std::min(scale, inside / reach);
    }
    poly.m_localCenter = toBullet(c);
    poly.m_radius = innerRadius(p, c);
    poly.m_extents = toBullet(Eigen::Vector3d(std::max(scale, 0.0) * half));
    poly.mC = toBullet(Eigen::Vector3d(p.bounds().max + p.bounds().min));
    poly.mE = toBullet(p.bounds().extent());
}

// A child hull whose points, polyhedral features and cached box a soft body's step moves in
// place (Bullet keeps the features behind a const accessor).
class PrimitiveHull : public btConvexHullShape {
public:
    // Polyhedral features filled by `fill` where the shape keeps them (no copy).
    // They keep their lanes (HullLanes.h): the separating-axis test of every new leaf pair
    // reads them.
    template <class Fill>
    void setFeatures(const Fill& fill) {
        if (!laned_) m_polyhedron = laned_ = new (btAlignedAlloc(sizeof(LanedPolyhedron), 16)) LanedPolyhedron;
        fill(*laned_);
        laned_->refreshLanes();
    }
    // The primitive's vertices as the hull's points, all at once (addPoint grows the array a
    // point at a time), and the cached box from its bounds: the box recalcLocalAabb would find
    // (the extreme vertices in float, plus the margin), bit for bit, without its six searches.
    void setPoints(const geometry::ConvexPolyhedron& p, btScalar margin) {
        const auto& vertices = p.vertices();
        m_unscaledPoints.resize(int(vertices.size()));
        for (size_t k = 0; k < vertices.size(); ++k) m_unscaledPoints[int(k)] = toBullet(vertices[k]);
        setMargin(margin);
        const btVector3 grow(margin, margin, margin);
        setCachedLocalAabb(toBullet(p.bounds().min) - grow, toBullet(p.bounds().max) + grow);
    }
    // The inner sphere a hull built over `p` has (moveTo keeps the sphere it had).
    void setInnerRadius(const geometry::ConvexPolyhedron& p) {
        m_polyhedron->m_radius = innerRadius(p, p.massProperties(1.0).centerOfMass);
    }
    // Moves the hull onto `p` (the primitive moved by a rotation `r`); `restEdges` are the
    // rest primitive's unique edge directions.
    void moveTo(const geometry::ConvexPolyhedron& p, const btMatrix3x3& r, std::span<const btVector3> restEdges) {
        const auto& vertices = p.vertices();
        btVector3* points = getUnscaledPoints();
        btConvexPolyhedron& poly = *m_polyhedron;
        for (size_t k = 0; k < vertices.size(); ++k) poly.m_vertices[int(k)] = points[k] = toBullet(vertices[k]);
        for (size_t f = 0; f < p.planes().size(); ++f) {
            const geometry::Plane& plane = p.planes()[f];
            btScalar* m = poly.m_faces[int(f)].m_plane;
            m[0] = btScalar(plane.normal.x());
            m[1] = btScalar(plane.normal.y());
            m[2] = btScalar(plane.normal.z());
            m[3] = btScalar(-plane.offset);
        }
        poly.m_uniqueEdges.resize(int(restEdges.size())); // the built hull may have merged near-parallel ones
        for (size_t e = 0; e < restEdges.size(); ++e) poly.m_uniqueEdges[int(e)] = r * restEdges[e];
        const geometry::Aabb& box = p.bounds();
        poly.m_localCenter = toBullet(p.centerOfMass()); // massProperties would turn the inertia
        poly.m_extents.setZero();
        poly.mC = toBullet(Eigen::Vector3d(box.max + box.min));
        poly.mE = toBullet(box.extent());
        const btVector3 margin(getMargin(), getMargin(), getMargin());
        setCachedLocalAabb(toBullet(box.min) - margin, toBullet(box.max) + margin);
        laned_->refreshLanes();
    }

    // Bullet's rebuild would free the laned polyhedron (laned_ left dangling) for a plain one,
    // whose faces, merged by its own hull, need not be the primitive's that moveTo writes by
    // index. The primitive's exact features are already set: they stay.
    bool initializePolyhedralFeatures(int /*shiftVerticesByMargin*/ = 0) override { return m_polyhedron != nullptr; }
    // Bullet's copy into m_polyhedron would leave the lanes stale: they follow the copy. moveTo
    // writes the primitive's vertices and faces by index, so a polyhedron with other counts (a
    // hull Bullet built merges coplanar faces) would have it write past the arrays: refused.
    void setPolyhedralFeatures(btConvexPolyhedron& polyhedron) override {
        const int vertices = laned_->m_vertices.size(), faces = laned_->m_faces.size();
        if (polyhedron.m_vertices.size() != vertices || polyhedron.m_faces.size() != faces)
            throw InputError("GroupShape: a child hull's polyhedral features must keep its primitive's " +
                             std::to_string(vertices) + " vertices and " + std::to_string(faces) + " faces, got " +
                             std::to_string(polyhedron.m_vertices.size()) + " and " +
                             std::to_string(polyhedron.m_faces.size()));
        setFeatures([&](btConvexPolyhedron& poly) { copyFeatures(polyhedron, poly); });
    }

private:
    // `from`'s features into `to` of the same counts. Not btConvexPolyhedron's operator=: its
    // faces array copy-constructs each face over the live one, leaking the face's index array.
    static void copyFeatures(const btConvexPolyhedron& from, btConvexPolyhedron& to) {
        to.m_vertices = from.m_vertices;
        for (int f = 0; f < from.m_faces.size(); ++f) {
            to.m_faces[f].m_indices = from.m_faces[f].m_indices;
            std::copy_n(from.m_faces[f].m_plane, 4, to.m_faces[f].m_plane);
        }
        to.m_uniqueEdges = from.m_uniqueEdges;
        to.m_localCenter = from.m_localCenter;
        to.m_extents = from.m_extents;
        to.m_radius = from.m_radius;
        to.mC = from.mC;
        to.mE = from.mE;
    }

    LanedPolyhedron* laned_ = nullptr; // m_polyhedron, once setFeatures made it
};

// A hull over the primitive's vertices whose polyhedral features are our exact faces, so
// Bullet's convex-convex algorithm clips faces instead of computing a hull of its own. The
// features are built in place (setPolyhedralFeatures would copy them, an allocation per face:
// a break makes thousands of these hulls).
std::unique_ptr<btConvexHullShape> makeChildHull(const geometry::ConvexPolyhedron& p, btScalar margin) {
    auto hull = std::make_unique<PrimitiveHull>();
    hull->setPoints(p, margin);
    hull->setFeatures([&](btConvexPolyhedron& poly) { primitiveFeatures(p, poly); });
    return hull;
}

// Principal moments per kilogram about the body origin and axes, from the exact mass
// properties at unit density (the lead sets the real inertia; this is Bullet's fallback).
Eigen::Vector3d unitInertiaAboutOrigin(const std::vector<geometry::ConvexPolyhedron>& primitives) {
    geometry::MassProperties total;
    for (const auto& p : primitives) total += p.massProperties(1.0);
    const Eigen::Vector3d c = total.centerOfMass;
    const Eigen::Matrix3d atOrigin =
        total.inertia + total.mass * (c.squaredNorm() * Eigen::Matrix3d::Identity() - c * c.transpose());
    return atOrigin.diagonal() / total.mass;
}

} // namespace

void primitiveFeatures(const geometry::ConvexPolyhedron& p, btConvexPolyhedron& poly) {
    poly.m_vertices.reserve(int(p.vertices().size()));
    for (const auto& v : p.vertices()) poly.m_vertices.push_back(toBullet(v));
    poly.m_faces.resize(int(p.faces().size()));
    for (size_t f = 0; f < p.faces().size(); ++f) {
        btFace& face = poly.m_faces[int(f)];
        face.m_indices.reserve(int(p.faces()[f].size()));
        for (int i : p.faces()[f]) face.m_indices.push_back(i);
        const geometry::Plane& plane = p.planes()[f];
        face.m_plane[0] = btScalar(plane.normal.x());
        face.m_plane[1] = btScalar(plane.normal.y());
        face.m_plane[2] = btScalar(plane.normal.z());
        face.m_plane[3] = btScalar(-plane.offset); // Bullet's plane is n·x + w = 0
    }
    addUniqueEdges(p, poly);
    setInternalObjects(p, poly);
}

GroupShape::GroupShape(std::vector<geometry::ConvexPolyhedron> primitives, double margin)
    : primitives_(std::move(primitives)), margin_(btScalar(margin)) {
    if (primitives_.empty()) throw InputError("GroupShape: needs at least one primitive, got none");
    if (!std::isfinite(margin) || margin < 0.0)
        throw InputError("GroupShape: margin must be finite and >= 0, got " + std::to_string(margin));
    m_shapeType = kGroupShapeType;
    m_collisionMargin = margin_;

    children_.resize(primitives_.size()); // built on first use (child())
    contactSlack_ = 0.5 * double(gContactBreakingThreshold);
    buildTrees();
    updateBounds();
}

GroupShape::GroupShape(GroupShape& from, const std::vector<int>& indices,
                       const std::vector<geometry::ConvexPolyhedron>& rest)
    : contactPerPrimitive_(from.contactPerPrimitive_) {
    if (indices.empty() || indices.size() != rest.size())
        throw InputError("GroupShape: " + std::to_string(indices.size()) + " primitives to take with " +
                         std::to_string(rest.size()) + " rest primitives (needs at least one, one rest each)");
    if (!std::is_sorted(indices.begin(), indices.end(), std::less_equal<>()))
        throw InputError("GroupShape: the primitives to take must be strictly increasing");
    for (int i : indices)
        if (i < 0 || i >= from.primitiveCount() || from.primitives_[size_t(i)].vertices().empty())
            throw InputError("GroupShape: no primitive " + std::to_string(i) + " to take");
    for (int i : indices)
        if (!from.children_[size_t(i)]) from.buildHull(i);
    from.moveStaleHulls(); // the taken hulls come where from's last step put them
    margin_ = from.margin_;
    m_shapeType = kGroupShapeType;
    m_collisionMargin = margin_;
    contactSlack_ = 0.5 * double(gContactBreakingThreshold); // as a new shape's
    primitives_.reserve(indices.size());
    children_.reserve(indices.size());
    const bool edgesKnown = !from.restEdgeOffsets_.empty();
    if (edgesKnown) {
        size_t edges = 0;
        for (int i : indices) edges += size_t(from.restEdgeOffsets_[size_t(i) + 1] - from.restEdgeOffsets_[size_t(i)]);
        restEdges_.reserve(edges);
        restEdgeOffsets_.reserve(indices.size() + 1);
        restEdgeOffsets_.push_back(0);
    }
    for (size_t k = 0; k < indices.size(); ++k) {
        const size_t i = size_t(indices[k]);
        primitives_.push_back(std::move(from.primitives_[i]));
        children_.push_back(std::move(from.children_[i]));
        static_cast<PrimitiveHull&>(*children_.back()).setInnerRadius(rest[k]);
        if (!edgesKnown) continue;
        restEdges_.insert(restEdges_.end(), from.restEdges_.begin() + from.restEdgeOffsets_[i],
                          from.restEdges_.begin() + from.restEdgeOffsets_[i + 1]);
        restEdgeOffsets_.push_back(int(restEdges_.size()));
    }
    if (!edgesKnown) addRestEdges(rest);
    std::vector<geometry::Aabb> restBoxes;
    restBoxes.reserve(rest.size());
    geometry::Aabb restBox; // as updateBounds finds it
    for (const auto& p : rest) {
        restBoxes.push_back(p.bounds());
        restBox.extend(p.bounds());
    }
    buildTrees(restBoxes);
    localAabbMin_ = toBullet(restBox.min); // until fitBox()
    localAabbMax_ = toBullet(restBox.max);
    revision_ = 1; // then as setPrimitivePoses leaves it
    refitTrees();
}

void GroupShape::noteRemoval(const std::vector<int>& to) {
    if (!removals_.empty() && removals_.back().revision + 1 != revision_) removals_.clear();
    if (int(removals_.size()) == kRemovalChain) removals_.erase(removals_.begin());
    removals_.push_back({revision_, to});
}

std::vector<int> GroupShape::indexMapFrom(std::uint64_t since) const {
    // The chain of removals since then: revisions since + 1, since + 2, ..., the current one.
    const auto first = std::find_if(removals_.begin(), removals_.end(), [&](const Removal& r) { return r.revision == since + 1; });
    if (first == removals_.end() || removals_.back().revision != revision_) return {};
    std::vector<int> to = first->to;
    for (auto r = first + 1; r != removals_.end(); ++r)
        for (int& t : to)
            if (t >= 0) t = r->to[size_t(t)];
    return to;
}

void GroupShape::updateBounds() {
    geometry::Aabb all;
    for (const auto& p : primitives_) all.extend(p.bounds());
    localAabbMin_ = toBullet(all.min);
    localAabbMax_ = toBullet(all.max);
    unitInertia_.reset();
}

void GroupShape::replacePrimitives(const std::vector<int>& indices,
                                   const std::vector<geometry::ConvexPolyhedron>& replacements) {
    if (indices.size() != replacements.size())
        throw InputError("GroupShape::replacePrimitives: " + std::to_string(indices.size()) + " indices for " +
                         std::to_string(replacements.size()) + " primitives");
    buildAllHulls();  // the others keep the hulls their primitives would have given them
    moveStaleHulls(); // and the hulls a step would have given them
    for (size_t k = 0; k < indices.size(); ++k) {
        const int i = indices[k];
        if (i < 0 || i >= primitiveCount())
            throw InputError("GroupShape::replacePrimitives: no primitive " + std::to_string(i));
        primitives_[i] = replacements[k];
        children_[i] = makeChildHull(primitives_[i], margin_);
    }
    ++revision_;
    renumberedAt_ = revision_;
    removals_.clear();
    restEdgeOffsets_.clear(); // the replacements may have other edges
    restEdges_.clear();
    refitTrees();
    updateBounds();
}

void GroupShape::setPrimitivePoses(const std::vector<geometry::ConvexPolyhedron>& rest,
                                   std::span<const Eigen::Isometry3d> poses) {
    if (rest.size() != primitives_.size() || poses.size() != primitives_.size())
        throw InputError("GroupShape::setPrimitivePoses: " + std::to_string(rest.size()) + " rest primitives and " +
                         std::to_string(poses.size()) + " poses for " + std::to_string(primitives_.size()) +
                         " primitives");
    if (restEdgeOffsets_.empty()) addRestEdges(rest);
    buildAllHulls(); // a hull is moved from where it was built, so it is built before the move
    ++revision_;
    removals_.clear();
    hullTurns_.resize(primitives_.size());
    staleHulls_.assign(primitives_.size(), 1);
    for (size_t i = 0; i < primitives_.size(); ++i) {
        primitives_[i].moveTo(rest[i], poses[i]);
        hullTurns_[i] = toBullet(Eigen::Matrix3d(poses[i].linear()));
    }
    refitTrees();
    fitBox();
}

void GroupShape::buildHull(int i) const { children_[size_t(i)] = makeChildHull(primitives_[size_t(i)], margin_); }

void GroupShape::buildAllHulls() const {
    for (size_t i = 0; i < children_.size(); ++i)
        if (!children_[i] && !primitives_[i].vertices().empty()) buildHull(int(i));
}

void GroupShape::moveHull(int i) const {
    const size_t k = size_t(i);
    const std::span<const btVector3> edges(restEdges_.data() + restEdgeOffsets_[k],
                                           size_t(restEdgeOffsets_[k + 1] - restEdgeOffsets_[k]));
    static_cast<PrimitiveHull&>(*children_[k]).moveTo(primitives_[k], hullTurns_[k], edges);
    staleHulls_[k] = 0;
}

void GroupShape::moveStaleHulls() {
    for (size_t i = 0; i < staleHulls_.size(); ++i)
        if (staleHulls_[i]) moveHull(int(i));
    staleHulls_.clear();
}

void GroupShape::fitBox() {
    localAabbMin_ = toBullet(tree_.bounds().min);
    localAabbMax_ = toBullet(tree_.bounds().max);
}

void GroupShape::addRestEdges(const std::vector<geometry::ConvexPolyhedron>& rest) {
    restEdgeOffsets_.push_back(0);
    for (const auto& p : rest) {
        btConvexPolyhedron edges;
        addUniqueEdges(p, edges);
        for (int e = 0; e < edges.m_uniqueEdges.size(); ++e) restEdges_.push_back(edges.m_uniqueEdges[e]);
        restEdgeOffsets_.push_back(int(restEdges_.size()));
    }
}

void GroupShape::refitTrees() {
    boxes_.resize(primitives_.size());
    for (size_t i = 0; i < primitives_.size(); ++i) boxes_[i] = primitives_[i].bounds();
    tree_.refit(boxes_);
    contactTreeStale_ = true;
}

void GroupShape::refitContactTree() const {
    // The contact tree is stale only from refitTrees on, whose boxes_ are the primitives'
    // bounds: read from one array, not from 5,000 primitives a few cache lines apart.
    grownBoxes_.resize(primitives_.size());
    for (size_t i = 0; i < primitives_.size(); ++i) grownBoxes_[i] = boxes_[i].inflated(contactSlack_);
    contactTree_.refit(grownBoxes_);
    contactTreeStale_ = false;
}

void GroupShape::removePrimitives(const std::vector<int>& indices, std::vector<geometry::ConvexPolyhedron> added) {
    std::vector<int> to(primitives_.size(), 0);
    for (int i : indices) {
        if (i < 0 || i >= primitiveCount())
            throw InputError("GroupShape::removePrimitives: no primitive " + std::to_string(i));
        to[i] = -1;
    }
    if (added.empty() && std::find(to.begin(), to.end(), 0) == to.end())
        throw InputError("GroupShape::removePrimitives: would remove all " + std::to_string(primitiveCount()) +
                         " primitives");
    moveStaleHulls(); // the survivors take their hulls along, where the last step put them
    if (contactTreeStale_) refitContactTree(); // its kept branches keep their boxes
    ++revision_;
    // Survivors move forward in order, each with its own child hull.
    int kept = 0;
    for (size_t i = 0; i < primitives_.size(); ++i) {
        if (to[i] < 0) continue;
        to[i] = kept;
        if (size_t(kept) != i) {
            primitives_[kept] = std::move(primitives_[i]);
            children_[kept] = std::move(children_[i]);
        }
        ++kept;
    }
    primitives_.erase(primitives_.begin() + long(kept), primitives_.end());
    children_.erase(children_.begin() + long(kept), children_.end());
    renumberedAt_ = revision_;
    if (!added.empty()) removals_.clear();
    else noteRemoval(to);
    std::vector<geometry::Aabb> boxes, grown;
    for (auto& p : added) {
        boxes.push_back(p.bounds());
        grown.push_back(p.bounds().inflated(contactSlack_));
        children_.emplace_back(); // built on first use
        primitives_.push_back(std::move(p));
    }
    keepRestEdges(to, added.empty());
    tree_.removeAndAppend(to, boxes);
    contactTree_.removeAndAppend(to, grown);
    updateBounds();
}

void GroupShape::fillPrimitives(const std::vector<int>& removed, std::vector<geometry::ConvexPolyhedron> added) {
    const geometry::HoleFilling slots = startFilling(removed, int(added.size()));
    for (size_t j = 0; j < added.size(); ++j) primitives_[size_t(slots.addedAt[j])] = std::move(added[j]);
    finishFilling(removed, slots);
}

void GroupShape::fillPrimitives(const std::vector<int>& removed, const std::vector<geometry::ConvexPolyhedron>& edited,
                                int added, const Eigen::Isometry3d& toShape) {
    const size_t left = size_t(primitiveCount()) - removed.size() + size_t(std::max(added, 0));
    if (edited.size() != left) // before any change (`removed` is checked by startFilling, first too)
        throw InputError("GroupShape::fillPrimitives: " + std::to_string(edited.size()) +
                         " edited primitives given, the edit leaves " + std::to_string(left));
    const geometry::HoleFilling slots = startFilling(removed, added);
    // Hinted: a piece overwrites a removed primitive's blocks, all over the shape (as freeing).
    const auto addedAt = [&](size_t k) { return slots.addedAt[k]; };
    for (size_t k = 0; k < slots.addedAt.size(); ++k) {
        geometry::prefetchPolyhedraAhead(primitives_, addedAt, slots.addedAt.size(), k);
        primitives_[size_t(slots.addedAt[k])].assignMoved(edited[size_t(slots.addedAt[k])], toShape);
    }
    finishFilling(removed, slots);
}

geometry::HoleFilling GroupShape::startFilling(const std::vector<int>& removed, int added) {
    const int count = primitiveCount();
    for (size_t k = 0; k < removed.size(); ++k)
        if (removed[k] < 0 || removed[k] >= count || (k > 0 && removed[k] <= removed[k - 1]))
            throw InputError("GroupShape::fillPrimitives: removed primitives must be ascending indices below " +
                             std::to_string(count) + " (" + std::to_string(removed[k]) + " is not)");
    if (added == 0 && int(removed.size()) == count)
        throw InputError("GroupShape::fillPrimitives: would remove all " + std::to_string(count) + " primitives");
    moveStaleHulls();
    if (contactTreeStale_) refitContactTree();
    ++revision_;
    renumberedAt_ = revision_;
    removals_.clear();
    geometry::HoleFilling slots = geometry::fillHoles(count, removed, added);
    const auto holeAt = [&](size_t k) { return slots.moves[k].second; };
    for (size_t k = 0; k < slots.moves.size(); ++k) {
        geometry::prefetchPolyhedraAhead(primitives_, holeAt, slots.moves.size(), k); // frees the hole's
        const auto [from, to] = slots.moves[k];
        primitives_[size_t(to)] = std::move(primitives_[size_t(from)]);
        children_[size_t(to)] = std::move(children_[size_t(from)]);
    }
    primitives_.resize(std::max(size_t(count), size_t(slots.size)));
    children_.resize(primitives_.size());
    for (const int at : slots.addedAt) children_[size_t(at)].reset(); // built on first use
    return slots;
}

void GroupShape::finishFilling(const std::vector<int>& removed, const geometry::HoleFilling& slots) {
    std::vector<geometry::Aabb> boxes, grown;
    boxes.reserve(slots.addedAt.size());
    grown.reserve(slots.addedAt.size());
    for (const int at : slots.addedAt) {
        boxes.push_back(primitives_[size_t(at)].bounds());
        grown.push_back(primitives_[size_t(at)].bounds().inflated(contactSlack_));
    }
    primitives_.resize(size_t(slots.size));
    children_.resize(size_t(slots.size));
    restEdgeOffsets_.clear();
    restEdges_.clear();
    tree_.fillHoles(removed, slots, boxes);
    contactTree_.fillHoles(removed, slots, grown);
    // The tree's root box is the union of the primitives' boxes (min and max are exact in any
    // order): no pass over every primitive.
    localAabbMin_ = toBullet(tree_.bounds().min);
    localAabbMax_ = toBullet(tree_.bounds().max);
    unitInertia_.reset();
}

void GroupShape::keepRestEdges(const std::vector<int>& to, bool nothingAdded) {
    if (!nothingAdded || restEdgeOffsets_.empty()) {
        // Added primitives come without their rest layout: the next soft step finds every
        // primitive's edges again from the rest it is given.
        restEdgeOffsets_.clear();
        restEdges_.clear();
        return;
    }
    // Each survivor's edges move forward with it, so the next soft step finds none again (a
    // torn soft body keeping its larger part would otherwise redo all of them).
    size_t kept = 0;
    std::vector<int> offsets{0};
    offsets.reserve(restEdgeOffsets_.size());
    for (size_t i = 0; i < to.size(); ++i) {
        if (to[i] < 0) continue;
        for (int e = restEdgeOffsets_[i]; e < restEdgeOffsets_[i + 1]; ++e) restEdges_[kept++] = restEdges_[size_t(e)];
        offsets.push_back(int(kept));
    }
    restEdges_.resize(kept);
    restEdgeOffsets_ = std::move(offsets);
}

GroupShape::~GroupShape() = default;

void GroupShape::buildTrees() {
    std::vector<geometry::Aabb> boxes;
    boxes.reserve(primitives_.size());
    for (const auto& p : primitives_) boxes.push_back(p.bounds());
    buildTrees(boxes);
    // The copy of the tree grown node by node is the one refitted to the grown boxes, bit for
    // bit (AabbTree::inflate), without a second box array and a pass that reads both children
    // of every node: the fragments' group shapes, 0.69 -> 0.36 M over five 16k-shell events.
    contactTree_.inflate(contactSlack_);
}

void GroupShape::buildTrees(const std::vector<geometry::Aabb>& boxes) {
    // A fracture's edit of the rest (removePrimitives) appends about two nodes per cut piece:
    // room for an eighth of the primitives cut keeps both node arrays where they are then.
    const size_t spare = 2 * (boxes.size() / 8 + 8);
    tree_ = geometry::AabbTree(boxes, spare);
    // Growing every box alike keeps their centres, by which the build splits: a copy of the
    // tree refitted to the grown boxes is the tree a build would give, at a fraction of the cost.
    contactTree_ = geometry::AabbTree(tree_, spare);
    contactTreeStale_ = false;
}

void GroupShape::getAabb(const btTransform& t, btVector3& aabbMin, btVector3& aabbMax) const {
    btTransformAabb(localAabbMin_, localAabbMax_, margin_, t, aabbMin, aabbMax);
}

void GroupShape::setLocalScaling(const btVector3& scaling) {
    if (scaling == unitScaling_ || scalingWarned_) return;
    scalingWarned_ = true;
    std::cerr << "shatter: GroupShape::setLocalScaling(" << scaling.x() << ", " << scaling.y() << ", " << scaling.z()
              << ") ignored: only (1, 1, 1) is supported; build the primitives at the size you need\n";
}

const btVector3& GroupShape::getLocalScaling() const { return unitScaling_; }

void GroupShape::calculateLocalInertia(btScalar mass, btVector3& inertia) const {
    if (!unitInertia_) unitInertia_ = unitInertiaAboutOrigin(primitives_);
    inertia = toBullet(Eigen::Vector3d(*unitInertia_ * double(mass)));
}

void GroupShape::setMargin(btScalar margin) {
    buildAllHulls();  // with the margin they were made with, then given the new one
    moveStaleHulls(); // each hull's box is recomputed from its points
    margin_ = margin;
    m_collisionMargin = margin;
    for (auto& child : children_) {
        child->setMargin(margin);
        child->recalcLocalAabb();
    }
}

namespace {

// Fans each face of the primitives the tree reports into triangles for a Bullet callback.
struct TriangleFan {
    const std::vector<geometry::ConvexPolyhedron>* primitives;
    btTriangleCallback* callback;

    void emit(int primitive) const {
        const geometry::ConvexPolyhedron& p = (*primitives)[primitive];
        const auto& v = p.vertices();
        int triangleIndex = 0;
        btVector3 tri[3];
        for (const auto& face : p.faces()) {
            tri[0] = toBullet(v[face[0]]);
            for (size_t k = 1; k + 1 < face.size(); ++k) {
                tri[1] = toBullet(v[face[k]]);
                tri[2] = toBullet(v[face[k + 1]]);
                callback->processTriangle(tri, primitive, triangleIndex++);
            }
        }
    }
};

} // namespace

void GroupShape::processAllTriangles(btTriangleCallback* callback, const btVector3& aabbMin, const btVector3& aabbMax) const {
    // Sweeps give the triangles our margin, so a primitive within the margin of the box counts.
    const geometry::Aabb box = geometry::Aabb{toEigen(aabbMin), toEigen(aabbMax)}.inflated(double(margin_));
    const TriangleFan fan{&primitives_, callback};
    tree_.query(box, [&fan](int i) { fan.emit(i); });
}

} // namespace shatter
