#include <shatter/bullet_ext/shape/GroupCollisionAlgorithms.h>

#include <shatter/bullet_ext/shape/FragmentHull.h>
#include <shatter/bullet_ext/shape/FragmentPairAlgorithm.h>
#include <shatter/bullet_ext/shape/HullLanes.h>
#include <shatter/bullet_ext/shape/HullPairContacts.h>
#include <shatter/bullet_ext/shape/NearBox.h>
#include <shatter/bullet_ext/shape/PolyhedronContacts.h>

#include <shatter/bullet_ext/Convert.h>
#include <shatter/bullet_ext/AttachedWorld.h>
#include <shatter/plugin/geometry/StampedScratch.h>

#include <BulletCollision/CollisionDispatch/btCollisionConfiguration.h>
#include <BulletCollision/CollisionDispatch/btCollisionObjectWrapper.h>
#include <BulletCollision/CollisionDispatch/btManifoldResult.h>
#include <BulletCollision/CollisionShapes/btBoxShape.h>
#include <BulletCollision/CollisionShapes/btStaticPlaneShape.h>
#include <BulletCollision/CollisionShapes/btTriangleCallback.h>
#include <BulletCollision/CollisionShapes/btTriangleShape.h>
#include <LinearMath/btPoolAllocator.h>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <optional>
#include <span>
#include <utility>

namespace shatter {

// ---------------------------------------------------------------------------------------
LeafCache::~LeafCache() {
    for (Entry& e : current_) release(dispatcher_, e);
    for (Entry& e : next_) release(dispatcher_, e);
}

LeafCache::Entry& LeafCache::touch(std::uint64_t key) {
    const auto it = std::lower_bound(current_.begin(), current_.end(), key,
                                     [](const Entry& e, std::uint64_t k) { return e.key < k; });
    if (it != current_.end() && it->key == key) {
        next_.push_back(*it);
        it->algorithm = nullptr; // moved on: end() must not free it
        it->manifold = nullptr;
    } else {
        next_.push_back(Entry{key});
    }
    return next_.back();
}

void LeafCache::end() {
    for (Entry& e : current_) release(dispatcher_, e);
    current_.swap(next_);
    next_.clear();
    std::sort(current_.begin(), current_.end(), [](const Entry& a, const Entry& b) { return a.key < b.key; });
}

void LeafCache::appendManifolds(btManifoldArray& manifolds) const {
    for (const Entry& e : current_) appendManifolds(e, manifolds);
}

void LeafCache::appendManifolds(const Entry& e, btManifoldArray& manifolds) {
    if (e.algorithm) {
        const int from = manifolds.size();
        e.algorithm->getAllContactManifolds(manifolds);
        int kept = from;
        for (int m = from; m < manifolds.size(); ++m)
            if (manifolds[m]->getNumContacts() > 0) manifolds[kept++] = manifolds[m];
        manifolds.resize(kept);
    }
    if (e.manifold && e.manifold->getNumContacts() > 0) manifolds.push_back(e.manifold);
}

void LeafCache::renumber(std::span<const int> to) {
    std::size_t kept = 0;
    for (Entry& e : current_) { // by key: the removed ones are freed in key order, as end() frees
        const int now = e.key < to.size() ? to[size_t(e.key)] : -1;
        if (now < 0) {
            release(dispatcher_, e);
            continue;
        }
        e.key = std::uint64_t(now); // a map keeps the survivors' order, so current_ stays sorted
        current_[kept++] = e;
    }
    current_.resize(kept);
}

void LeafCache::release(btDispatcher* dispatcher, Entry& e) {
    if (e.algorithm) {
        e.algorithm->~btCollisionAlgorithm();
        dispatcher->freeCollisionAlgorithm(e.algorithm);
    }
    if (e.manifold) dispatcher->releaseManifold(e.manifold);
    e.algorithm = nullptr;
    e.manifold = nullptr;
}

void LeafCache::releaseInKeyOrder(btDispatcher* dispatcher, std::vector<Entry>& entries) {
    // By (key, place): a sort of the hundred-byte entries themselves cost twice as much.
    thread_local std::vector<std::pair<std::uint64_t, std::size_t>> order; // reused: no allocation once warm
    order.clear();
    for (std::size_t k = 0; k < entries.size(); ++k) order.emplace_back(entries[k].key, k);
    std::sort(order.begin(), order.end());
    for (const auto& [key, place] : order) release(dispatcher, entries[place]);
    entries.clear();
}

namespace {

const GroupShape& groupOf(const btCollisionObjectWrapper* wrap) {
    return *static_cast<const GroupShape*>(wrap->getCollisionShape());
}

// Box in group coordinates grown by `grow` on every side.
geometry::Aabb grownBox(const btVector3& min, const btVector3& max, double grow) {
    return geometry::Aabb{toEigen(min), toEigen(max)}.inflated(grow);
}

// The contact breaking threshold Bullet gives the manifolds of this pair (as
// btCollisionDispatcher::getNewManifold computes it).
double breakingThreshold(const btDispatcher* dispatcher, const btCollisionObjectWrapper* a,
                         const btCollisionObjectWrapper* b) {
    const auto* d = static_cast<const btCollisionDispatcher*>(dispatcher);
    if (!(d->getDispatcherFlags() & btCollisionDispatcher::CD_USE_RELATIVE_CONTACT_BREAKING_THRESHOLD))
        return double(gContactBreakingThreshold);
    return double(btMin(a->getCollisionObject()->getCollisionShape()->getContactBreakingThreshold(gContactBreakingThreshold),
                        b->getCollisionObject()->getCollisionShape()->getContactBreakingThreshold(gContactBreakingThreshold)));
}

// Distance within which a pair still makes contact points: the breaking threshold plus the
// extra distance a closest-points query asks for.
double contactDistance(const btDispatcher* dispatcher, const btCollisionObjectWrapper* a,
                       const btCollisionObjectWrapper* b, const btManifoldResult* result) {
    return breakingThreshold(dispatcher, a, b) + double(result->m_closestPointDistanceThreshold);
}

ebtDispatcherQueryType leafQuery(const btManifoldResult* result) {
    return result->m_closestPointDistanceThreshold > 0 ? BT_CLOSEST_POINT_ALGORITHMS : BT_CONTACT_POINT_ALGORITHMS;
}

// Points the result's wrappers and shape identifiers at one leaf pair while its contacts are
// added, whichever order the result lists the two bodies in, and puts the wrappers back
// after. Contact callbacks then see the primitive (partId -1, index = primitive) and the
// triangle or compound child on the other side, as they would for Bullet's own shapes.
class LeafScope {
public:
    LeafScope(btManifoldResult* result, const btCollisionObjectWrapper* a, const btCollisionObjectWrapper* b)
        : result_(result), old0_(result->getBody0Wrap()), old1_(result->getBody1Wrap()) {
        if (result->getBody0Internal() != a->getCollisionObject()) std::swap(a, b);
        result->setBody0Wrap(a);
        result->setBody1Wrap(b);
        result->setShapeIdentifiersA(a->m_partId, a->m_index);
        result->setShapeIdentifiersB(b->m_partId, b->m_index);
    }
    ~LeafScope() {
        result_->setBody0Wrap(old0_);
        result_->setBody1Wrap(old1_);
    }
    LeafScope(const LeafScope&) = delete;
    LeafScope& operator=(const LeafScope&) = delete;

private:
    btManifoldResult* result_;
    const btCollisionObjectWrapper* old0_;
    const btCollisionObjectWrapper* old1_;
};

// Two convex hulls with polyhedral features: the pairs Bullet clips (HullPairContacts.h).
bool isHullPair(const btCollisionObjectWrapper* a, const btCollisionObjectWrapper* b) {
    const auto features = [](const btCollisionShape* s) {
        return s->getShapeType() == CONVEX_HULL_SHAPE_PROXYTYPE &&
               static_cast<const btPolyhedralConvexShape*>(s)->getConvexPolyhedron() != nullptr;
    };
    return features(a->getCollisionShape()) && features(b->getCollisionShape());
}

// What the leaf pairs of two groups share, made once per group pair: their bodies' relative
// pose (separatingFace), and body0 in body1's frame as the result's body0⁻¹ · body1 gives it
// when the result lists body1 first (a clip's LastClip).
struct LeafPoses {
    LeafPoses(const btTransform& t0, const btTransform& t1, std::uint64_t proofStep, double roundingScale)
        : pose(t0, t1), zeroInOne(t1.inverseTimes(t0)), proofStep(proofStep), roundingScale(roundingScale) {}
    RelativePose pose; // pose.bToA: body1 in body0's frame
    btTransform zeroInOne;
    std::uint64_t proofStep; // > 0: the group pair's step, and pairs found apart get an ApartProof
    // > 0: the coordinates' scale (m) in the leaves' tests, and a new pair apart by a face plane
    // by more than their rounding skips the full test (newPairApart).
    double roundingScale;
};

thread_local std::uint64_t skippedAsApart = 0;

// Bounds the float rounding of the tests a proof stands for, per metre of the coordinates they
// compute with: separatingFace's test of one face (vertices placed by a float transform, a
// dot product with the face normal, plus the plane's offset: about 20 units of float rounding,
// 6e-8), or the separating-axis test of a new pair along a face normal (both hulls placed in
// world coordinates, their spans compared: about 60 units, with the float rotations' own
// departure from orthonormal). 3e-5 of them leaves a factor of 8.
// It assumes the bodies' bases are orthonormal to a few float ulps, as Bullet's quaternion
// integration keeps them. provenApart needs no such assumption (it compares the
// relative-frame test with itself), but newPairApart does: it proves in the relative frame
// (RelativePose) what the full test computes in world coordinates, and the two agree only as
// far as the bases are orthonormal. An application's kinematic body driven by accumulated
// btTransform products can drift from orthonormal by more than this margin (about 1e-4 after
// 10^6 products); a new pair of such a body that overlaps by less than that drift times the
// coordinates' scale could then be skipped.
constexpr double kRoundingPerMetre = 3e-5;

// Whether a new hull pair's full test (polyhedronContacts: Bullet's separating-axis test, then
// clipping) provably finds a separating axis, and so adds nothing: a face plane of either hull
// has the other in front of it by more than both hulls' own vertices are in front of their
// planes (LanedPolyhedron::ownFront) plus the rounding of both tests at this scale. Then that
// face's normal separates the two hulls' spans as the full test computes them, whichever axis
// it finds first. Returns the face (separatingFace's numbering), or -1 (the full test runs).
// Most new pairs of two groups are apart by a face (the table's halves: 99 in 100), and this
// test costs a fifth of the full one (about 200 instructions, not 1,000). It assumes
// near-orthonormal body bases (kRoundingPerMetre).
int newPairApart(const btConvexPolyhedron& a, const btConvexPolyhedron& b, const LeafPoses& poses) {
    const LanedPolyhedron* lanedA = lanedPolyhedron(a);
    const LanedPolyhedron* lanedB = lanedPolyhedron(b);
    if (!lanedA || !lanedB || !(poses.roundingScale > 0)) return -1;
    const double gap = kRoundingPerMetre * (1 + poses.roundingScale) + std::max(lanedA->ownFront(), lanedB->ownFront());
    return separatingFace(a, b, poses.pose, btScalar(gap * (1 + 1e-6)), -1);
}

// The proof that face `face` of the pair (an index into a's faces, then b's: separatingFace's)
// keeps a and b apart, placed by `pose`: the least distance of the other hull's vertices in
// front of the face, in double arithmetic on the floats the test reads (so exact to 1e-16 of
// them), less a rounding margin for the test that will be skipped. No proof (budget -1) when
// nothing is left of the distance.
ApartProof proveApart(const btConvexPolyhedron& a, const btConvexPolyhedron& b, const RelativePose& pose, int face,
                      std::uint64_t step) {
    const int facesA = a.m_faces.size();
    const bool onB = face >= facesA;
    const btConvexPolyhedron& planes = onB ? b : a;
    const btConvexPolyhedron& other = onB ? a : b;
    const btTransform& toPlanes = onB ? pose.aToB : pose.bToA;
    const btScalar* plane = planes.m_faces[onB ? face - facesA : face].m_plane;
    const Eigen::Vector3d n(plane[0], plane[1], plane[2]);
    const Eigen::Matrix3d r = toEigen(toPlanes.getBasis());
    const Eigen::Vector3d t = toEigen(toPlanes.getOrigin());
    const int count = other.m_vertices.size();
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    double gap = std::numeric_limits<double>::infinity();
    for (int v = 0; v < count; ++v) {
        const Eigen::Vector3d x = toEigen(other.m_vertices[v]);
        sum += x;
        gap = std::min(gap, n.dot(r * x + t) + double(plane[3]));
    }
    ApartProof proof;
    const Eigen::Vector3f centre = (sum / double(std::max(count, 1))).cast<float>();
    double radius = 0;
    for (int v = 0; v < count; ++v)
        radius = std::max(radius, (toEigen(other.m_vertices[v]) - centre.cast<double>()).norm());
    const double budget =
        gap - kRoundingPerMetre * (1 + double(centre.norm()) + radius + std::abs(double(plane[3])));
    if (count == 0 || !(budget > 0)) return proof;
    for (int k = 0; k < 3; ++k) proof.centre[k] = centre[k];
    proof.radius = float(radius * (1 + 1e-6) + 1e-9);   // rounded up
    proof.budget = float(budget * (1 - 1e-6));          // rounded down
    proof.step = step;
    proof.onB = onB;
    return proof;
}

// Runs the leaf pair (a, b) with the child algorithm of its leaf entry (created on first
// contact; it owns its manifold). (a, b) are in the group algorithm's (body0, body1) order,
// so the child reports its normal on body1 as Bullet expects. `withFragment`: the side that is
// not a group's leaf is a lattice fragment's hull (FragmentHull), known once per group pair
// (the cast, twice per leaf, cost as much as a tenth of the leaf's own work). `poses`: a's
// and b's transforms relative to each other, when a and b are two groups' leaves, else null.
void runLeaf(LeafCache::Entry& entry, btDispatcher* dispatcher, const btCollisionObjectWrapper* a,
             const btCollisionObjectWrapper* b, bool withFragment, const btDispatcherInfo& info, btManifoldResult* result,
             const LeafPoses* poses = nullptr) {
    // Lattice fragments' pairs keep their own test and a clip every step (HullPairContacts.h).
    const bool hullContacts = !withFragment && isHullPair(a, b) && result->m_closestPointDistanceThreshold <= 0;
    // A new leaf runs Bullet's algorithm once, so it has its manifold from its first step as
    // in Bullet's own flow: empty manifolds join bodies into the islands the lattice's replay
    // works on (skipping their creation turned the wall's 255 fragments at seed 1 into 860).
    const bool fresh = !entry.held();
    // Without empty manifolds (HullPairContacts::keepEmptyLeafManifolds off) a hull pair's own
    // manifold is made when it is clipped and freed when it is left empty, in a world whose
    // solver takes the others in an order independent of their places (OrderedContacts.h,
    // AttachedWorld.h: asked at every leaf, so a world the Plugin returns to Bullet's order
    // keeps its empty manifolds from that step on). A kinematic body's manifolds, empty too,
    // wake what they touch (Bullet's island manager): those stay. Asked only of an empty
    // manifold (the world's list is walked: 600,000 times in the table's frames 52-58).
    const auto dropEmpty = [&] {
        return !hullPairContacts().keepEmptyLeafManifolds && dispatcherOrdersContacts(dispatcher) &&
               !a->getCollisionObject()->isKinematicObject() && !b->getCollisionObject()->isKinematicObject();
    };
    // Where the pair stood at this clip (LastClip): the result's body0⁻¹ · body1, in the order
    // the result lists the pair (LeafScope).
    const auto markClipped = [&] {
        if (poses && result->getBody0Wrap() == a)
            clipped(entry.lastClip, poses->pose.bToA);
        else if (poses && result->getBody0Wrap() == b)
            clipped(entry.lastClip, poses->zeroInOne);
        else
            clipped(entry.lastClip, *result);
    };
    const auto releaseIfEmpty = [&] {
        if (entry.manifold && entry.manifold->getNumContacts() == 0 && dropEmpty()) {
            dispatcher->releaseManifold(entry.manifold);
            entry.manifold = nullptr;
        }
    };
    // Neither side is a lattice fragment's hull here: a group's leaves are its own hulls (GroupShape's
    // PrimitiveHull), and the other side's hull would be `withFragment`. (Asking, by a dynamic_cast
    // per side, was 8% of the table's instructions: 38,000 new pairs at every shrink.)
    assert(!hullContacts || (!isFragmentHull(a->getCollisionShape()) && !isFragmentHull(b->getCollisionShape())));
    if (fresh && hullContacts) {
        // Bullet's algorithm for two hulls (btConvexConvexAlgorithm, with the separating-axis
        // test on) makes its manifold and fills it by its test and clip, which
        // polyhedronContacts does bit for bit at a fraction of the cost; the pair then needs
        // no algorithm, only the manifold, made and freed in the same order. Every shrink of
        // a group makes all its pairs new: the table's two broken halves, 38,000 pairs at once.
        entry.manifold = dispatcher->getNewManifold(a->getCollisionObject(), b->getCollisionObject());
        entry.seen = true;
        const LeafScope scope(result, a, b);
        result->setPersistentManifold(entry.manifold);
        // Apart by a face (its index kept as the pair's hint): the full test would add nothing.
        const int apartFace = poses && hullPairContacts().skipProvenApart
                                  ? newPairApart(*polyhedronOf(a), *polyhedronOf(b), *poses)
                                  : -1;
        if (apartFace >= 0)
            entry.separatingFace = apartFace;
        else
            polyhedronContacts(*polyhedronOf(a), a->getWorldTransform(), *polyhedronOf(b), b->getWorldTransform(),
                               entry.manifold->getContactBreakingThreshold(), *result, &entry.separatingAxis);
        result->refreshContactPoints();
        markClipped();
        releaseIfEmpty();
        return;
    }
    if (fresh)
        entry.algorithm = withFragment && isHullPair(a, b) && leafQuery(result) == BT_CONTACT_POINT_ALGORITHMS
                              ? newFragmentPair(dispatcher, a, b)
                              : dispatcher->findAlgorithm(a, b, nullptr, leafQuery(result));
    btCollisionAlgorithm* algorithm = entry.algorithm;
    if (!entry.held()) return;
    // A hull pair's one manifold: its own (above), or its algorithm's; none while its own was
    // left empty.
    const auto hullManifold = [&entry] {
        return entry.manifold ? entry.manifold : entry.algorithm ? soleManifold(*entry.algorithm) : nullptr;
    };
    if (hullContacts && !fresh) {
        // Most leaf pairs the trees report are apart (the vase's heap: 9 in 10), and Bullet's
        // separating-axis test tries every face and edge pair to find that out. A face plane
        // with the other hull in front of it proves it at a fraction of the cost, mostly the
        // same face as last step. Such a pair gets what Bullet gives a separated pair: no new
        // points, and its kept points refreshed (dropped beyond the breaking threshold).
        entry.separatingFace = poses ? separatingFace(*polyhedronOf(a), *polyhedronOf(b), poses->pose, 0, entry.separatingFace)
                                     : separatingFace(a, b, 0, entry.separatingFace);
        entry.apart = ApartProof{};
        if (entry.separatingFace >= 0) {
            btPersistentManifold* manifold = hullManifold();
            if (manifold && manifold->getNumContacts() > 0) {
                const LeafScope scope(result, a, b);
                result->setPersistentManifold(manifold);
                result->refreshContactPoints();
                releaseIfEmpty();
            } else if (poses && poses->proofStep > 0 && hullPairContacts().skipProvenApart) {
                // Apart with nothing to refresh: the group pair may skip the next runs
                // (GroupGroupAlgorithm::provenApart).
                entry.apart = proveApart(*polyhedronOf(a), *polyhedronOf(b), poses->pose, entry.separatingFace,
                                         poses->proofStep);
            }
            return;
        }
    }
    // A seen pair without a manifold is a hull pair whose own manifold was left empty.
    if (hullContacts && !algorithm && !entry.manifold)
        entry.manifold = dispatcher->getNewManifold(a->getCollisionObject(), b->getCollisionObject());
    const LeafScope scope(result, a, b);
    if (btPersistentManifold* manifold = hullContacts ? hullManifold() : nullptr) {
        result->setPersistentManifold(manifold);
        if (!keptWithoutClip(*manifold, *result, entry.lastClip, hullPairContacts())) {
            // Bullet's algorithm would do the same (test, clip, refresh of its own manifold), at
            // several times the cost of the test (PolyhedronContacts.h).
            polyhedronContacts(*polyhedronOf(a), a->getWorldTransform(), *polyhedronOf(b), b->getWorldTransform(),
                               manifold->getContactBreakingThreshold(), *result, &entry.separatingAxis);
            result->refreshContactPoints();
            markClipped();
        }
        releaseIfEmpty();
        return;
    }
    // An entry with only its own manifold is a hull pair's, whose contacts come from the branch
    // above while the pair is in this algorithm (its shapes change only out of the world).
    if (!algorithm) return;
    algorithm->processCollision(a, b, info, result);
    if (hullContacts) markClipped();
}

// A group's hull leaf against a box (HullPairContacts::boxLeavesClipped), into the leaf's
// manifold, made on first contact as Bullet's algorithm would make its own. `child` is the
// leaf's wrapper, `boxWrap` the box's; `polyhedron` the box's faces (its surface).
struct BoxLeaf {
    btDispatcher* dispatcher;
    const btCollisionObjectWrapper* boxWrap;
    const btConvexPolyhedron* polyhedron;
    btVector3 half; // the box's surface
    bool groupIsBody0;
    bool onePoint; // one contact per primitive (GroupShape::contactPerPrimitive), or a closest-points query
    btManifoldResult* result;

    void operator()(LeafCache::Entry& entry, const btCollisionObjectWrapper* child) const {
        const btCollisionObjectWrapper* a = groupIsBody0 ? child : boxWrap;
        const btCollisionObjectWrapper* b = groupIsBody0 ? boxWrap : child;
        if (!entry.manifold) entry.manifold = dispatcher->getNewManifold(a->getCollisionObject(), b->getCollisionObject());
        const LeafScope scope(result, a, b);
        result->setPersistentManifold(entry.manifold);
        const btScalar threshold = entry.manifold->getContactBreakingThreshold() + result->m_closestPointDistanceThreshold;
        const auto* hull = static_cast<const btConvexHullShape*>(child->getCollisionShape());
        const btConvexPolyhedron& features = *hull->getConvexPolyhedron();
        // Bullet's GJK gives a soft group one point a step, a margin off the hull: the same, from
        // the separating-axis test in the box's frame. A rigid group gets the clipped face, and
        // while it is a hair apart (nothing to clip) its nearest point at that distance, as
        // Bullet's clipping does for hulls within the threshold, so that a fresh query of a
        // body resting on the box still finds the contact.
        const bool overlap =
            !onePoint && (groupIsBody0 ? polyhedronContacts(features, a->getWorldTransform(), *polyhedron,
                                                            b->getWorldTransform(), threshold, *result)
                                       : polyhedronContacts(*polyhedron, a->getWorldTransform(), features,
                                                            b->getWorldTransform(), threshold, *result));
        BoxContact c;
        if (!overlap && hullBoxContact(features, child->getWorldTransform(), onePoint ? hull->getMargin() : btScalar(0),
                                       half, boxWrap->getWorldTransform(), threshold, c)) {
            // The result's body1 is b: its normal points from b towards a.
            if (groupIsBody0)
                result->addContactPoint(c.normal, c.onBox, c.distance);
            else
                result->addContactPoint(-c.normal, c.onBox + c.normal * c.distance, c.distance);
        }
        result->refreshContactPoints();
    }
};

// For contacts, hull-hull leaf pairs run with Bullet's separating-axis test on: for two
// hulls with polyhedral features it gives the exact face or edge normal before clipping,
// where the default (GJK and EPA on the margin-grown shapes) tilts normals at tiny
// penetrations next to edges (a table leg standing across the seam of two floor slabs).
// Pairs with a shape that has no polyhedral features (sphere, capsule, btBoxShape) take GJK
// either way. Closest-points queries keep GJK, which also measures separated pairs.
btDispatcherInfo leafInfo(const btDispatcherInfo& info, const btManifoldResult* result) {
    btDispatcherInfo leaf = info;
    if (result->m_closestPointDistanceThreshold <= 0) leaf.m_enableSatConvex = true;
    return leaf;
}

bool boxesWithin(const geometry::Aabb& a, const geometry::Aabb& b, const BoxTurn& turn, double slack) {
    return NearBox(b, turn, slack).within(a);
}

// Body1's primitive boxes turned into body0's frame (NearBox) for one turn and slack, each made
// when a pair with it is first tested and reused by the others with the same j. A group pair's
// pairs meet each of body1's primitives with several of body0's: making j's box for every pair
// (a hundred-odd instructions, as much as the test) was a tenth of the table's group pairs.
class NearBoxes {
public:
    NearBoxes(const GroupShape& g1, const BoxTurn& turn, double slack)
        : g1_(g1), turn_(turn), slack_(slack), boxes_(std::size_t(g1.primitiveCount())) {}

    // The same box NearBox(g1's primitive j, turn, slack) gives.
    const NearBox& operator[](int j) {
        return boxes_.get(std::size_t(j), [&] { return NearBox(g1_.primitives()[j].bounds(), turn_, slack_); });
    }

private:
    const GroupShape& g1_;
    const BoxTurn& turn_;
    double slack_;
    geometry::StampedScratch<NearBox> boxes_;
};

// The farthest corner of `box` from the origin, at most.
double boxReach(const geometry::Aabb& box) { return box.min.cwiseAbs().cwiseMax(box.max.cwiseAbs()).norm(); }

// How far a point of `box` (the coordinates `motion` moves) can go under `motion`: its shift
// plus its turn angle times the farthest corner of the box from the origin.
double motionBound(const Eigen::Isometry3d& motion, const geometry::Aabb& box) {
    return motion.translation().norm() + Eigen::AngleAxisd(motion.linear()).angle() * boxReach(box);
}

std::uint64_t pairKey(int i, int j) { return (std::uint64_t(std::uint32_t(i)) << 32) | std::uint32_t(j); }

} // namespace

// ---------------------------------------------------------------------------------------
GroupAlgorithmBase::GroupAlgorithmBase(const btCollisionAlgorithmConstructionInfo& ci,
                                       const btCollisionObjectWrapper* body0, const btCollisionObjectWrapper* body1)
    : btActivatingCollisionAlgorithm(ci, body0, body1), leaves_(m_dispatcher) {}

void GroupAlgorithmBase::getAllContactManifolds(btManifoldArray& manifolds) { leaves_.appendManifolds(manifolds); }

std::optional<std::vector<int>> SeenRevision::update(const GroupShape& group) {
    if (group.revision() == revision) return std::nullopt;
    std::optional<std::vector<int>> to;
    if (group.renumberedSince(revision)) to = group.indexMapFrom(revision);
    revision = group.revision();
    return to;
}

void GroupVersusAlgorithm::followRenumbering(const GroupShape& group) {
    if (!seen_) {
        seen_ = SeenRevision{group.revision()};
        return;
    }
    // The points themselves were renumbered with the edit (RemovalInWorld.h).
    if (const std::optional<std::vector<int>> to = seen_->update(group)) leaves_.renumber(*to);
}

// ---------------------------------------------------------------------------------------
void GroupConvexAlgorithm::processCollision(const btCollisionObjectWrapper* body0,
                                            const btCollisionObjectWrapper* body1, const btDispatcherInfo& info,
                                            btManifoldResult* result) {
    const auto [groupWrap, otherWrap] = sides(body0, body1);
    const GroupShape& group = groupOf(groupWrap);
    followRenumbering(group);
    const btTransform otherToGroup = groupWrap->getWorldTransform().inverseTimes(otherWrap->getWorldTransform());
    const double reach = double(group.getMargin()) + contactDistance(m_dispatcher, body0, body1, result);

    // The other shape's own box (margin included), for the tree and for each candidate.
    btVector3 min, max;
    otherWrap->getCollisionShape()->getAabb(btTransform::getIdentity(), min, max);
    const geometry::Aabb otherBox{toEigen(min), toEigen(max)};
    const Eigen::Isometry3d otherToGroupE = toEigen(otherToGroup);

    struct Visit {
        LeafCache& leaves;
        btDispatcher* dispatcher;
        const GroupShape& group;
        const btCollisionObjectWrapper* groupWrap;
        const btCollisionObjectWrapper* otherWrap;
        bool groupIsBody0;
        const btDispatcherInfo& info;
        btManifoldResult* result;
        const NearBox& near; // the other shape's box, in group coordinates
        bool otherIsFragment;

        const BoxLeaf* box; // against a box, or null

        void operator()(int i) const {
            if (!near.within(group.primitives()[i].bounds())) return;
            const btCollisionObjectWrapper child(groupWrap, &group.child(i), groupWrap->getCollisionObject(),
                                                 groupWrap->getWorldTransform(), -1, i);
            if (box && group.child(i).getConvexPolyhedron()) {
                (*box)(leaves.touch(std::uint64_t(i)), &child);
                return;
            }
            const btCollisionObjectWrapper* a = groupIsBody0 ? &child : otherWrap;
            const btCollisionObjectWrapper* b = groupIsBody0 ? otherWrap : &child;
            runLeaf(leaves.touch(std::uint64_t(i)), dispatcher, a, b, otherIsFragment, info, result);
        }
    };
    const btDispatcherInfo leaf = leafInfo(info, result);
    const btCollisionShape* otherShape = otherWrap->getCollisionShape();
    const bool boxLeaves = (group.contactPerPrimitive() ? hullPairContacts().softBoxContacts
                                                         : hullPairContacts().boxLeavesClipped) &&
                           otherShape->getShapeType() == BOX_SHAPE_PROXYTYPE;
    const btVector3 half = boxLeaves ? static_cast<const btBoxShape*>(otherShape)->getHalfExtentsWithMargin() : btVector3(0, 0, 0);
    // A closest-points query measures the margin-grown shapes, as GJK does: the one point.
    const bool query = result->m_closestPointDistanceThreshold > 0;
    const BoxLeaf boxLeaf{m_dispatcher, otherWrap, boxLeaves ? &boxFeatures(half) : nullptr,
                          half, groupIsBody0_, group.contactPerPrimitive() || query, result};
    const BoxTurn turn(otherToGroupE);
    const NearBox near(otherBox, turn, reach);
    const Visit visit{leaves_, m_dispatcher, group, groupWrap, otherWrap, groupIsBody0_, leaf, result,
                      near, isFragmentHull(otherShape), boxLeaves ? &boxLeaf : nullptr};
    const geometry::Aabb box = geometry::transformedAabb(otherBox, otherToGroupE).inflated(reach);
    leaves_.begin();
    group.tree().query(box, [&visit](int i) { visit(i); });
    leaves_.end();
}

const btConvexPolyhedron& GroupConvexAlgorithm::boxFeatures(const btVector3& halfExtents) {
    if (!box_ || boxHalf_ != halfExtents) {
        box_ = std::make_unique<btConvexPolyhedron>(boxPolyhedron(halfExtents));
        boxHalf_ = halfExtents;
    }
    return *box_;
}

// ---------------------------------------------------------------------------------------
namespace {

using Candidate = GroupPlaneAlgorithm::Candidate;

// A tangent of the plane from a fixed direction in group coordinates that no box edge is
// likely to be parallel to, so "farthest along it" has no near ties that noise could flip.
Eigen::Vector3d stableTangent(const Eigen::Vector3d& n) {
    for (const Eigen::Vector3d& w : {Eigen::Vector3d(1.0, 0.414, 0.173), Eigen::Vector3d(0.173, 1.0, 0.414)}) {
        const Eigen::Vector3d u = w - n * n.dot(w);
        if (u.squaredNorm() > 0.1) return u;
    }
    return Eigen::Vector3d(0.414, 0.173, 1.0) - n * n.z();
}

// Up to four candidates spanning the support polygon: the deepest (among nearly equally deep
// ones the farthest along a fixed tangent, so a resting body keeps the same points from step
// to step and Bullet's warm starting keeps working), the farthest from it, the widest
// triangle, and the point farthest outside that triangle.
int selectSupport(std::span<const Candidate> c, const Eigen::Vector3d& n, double depthTolerance, int chosen[4]) {
    const int count = int(c.size());
    if (count <= 4) {
        for (int i = 0; i < count; ++i) chosen[i] = i;
        return count;
    }
    double deepest = c[0].distance;
    for (const auto& k : c) deepest = std::min(deepest, k.distance);
    const Eigen::Vector3d u = stableTangent(n);
    int p0 = -1;
    for (int i = 0; i < count; ++i)
        if (c[i].distance <= deepest + depthTolerance && (p0 < 0 || u.dot(c[i].vertex) > u.dot(c[p0].vertex))) p0 = i;
    chosen[0] = p0;
    const auto inPlane = [&](int i) { return Eigen::Vector3d(c[i].vertex - n * n.dot(c[i].vertex)); };
    const Eigen::Vector3d a = inPlane(p0);

    int p1 = -1;
    double best = 1e-12;
    for (int i = 0; i < count; ++i)
        if (const double d = (inPlane(i) - a).squaredNorm(); d > best) best = d, p1 = i;
    if (p1 < 0) return 1;
    chosen[1] = p1;
    const Eigen::Vector3d b = inPlane(p1);

    const auto area = [&](const Eigen::Vector3d& p, const Eigen::Vector3d& q, int i) {
        return n.dot((q - p).cross(inPlane(i) - p));
    };
    int p2 = -1;
    best = 1e-12;
    for (int i = 0; i < count; ++i)
        if (const double s = std::abs(area(a, b, i)); s > best) best = s, p2 = i;
    if (p2 < 0) return 2;
    chosen[2] = p2;
    const Eigen::Vector3d d = inPlane(p2);

    // Orient the triangle counter-clockwise about n; "outside" an edge is then negative area.
    const bool ccw = area(a, b, p2) > 0;
    const Eigen::Vector3d tri[3] = {a, ccw ? b : d, ccw ? d : b};
    int p3 = -1;
    best = 1e-12;
    for (int i = 0; i < count; ++i) {
        double outside = 0.0;
        for (int e = 0; e < 3; ++e) outside = std::max(outside, -area(tri[e], tri[(e + 1) % 3], i));
        if (outside > best) best = outside, p3 = i;
    }
    if (p3 < 0) return 3;
    chosen[3] = p3;
    return 4;
}

// Puts the candidates within `band` of the deepest first and returns them, or all candidates
// when fewer than three are that deep. Points higher up are only speculative contacts; a
// support polygon spread over them would drop real contacts, and a body resting on many
// equally deep points (a torus on its ring) would rock from one chosen set to another.
std::span<const Candidate> carryingFirst(std::vector<Candidate>& c, double band) {
    if (c.empty()) return c;
    double deepest = c[0].distance;
    for (const auto& k : c) deepest = std::min(deepest, k.distance);
    const auto end = std::stable_partition(c.begin(), c.end(), [&](const Candidate& k) { return k.distance <= deepest + band; });
    const auto carrying = std::distance(c.begin(), end);
    return carrying >= 3 ? std::span<const Candidate>(c.data(), size_t(carrying)) : std::span<const Candidate>(c);
}

// The deepest candidate of each primitive (candidates arrive grouped by primitive).
std::vector<int> deepestPerPrimitive(const std::vector<Candidate>& c) {
    std::vector<int> out;
    for (int k = 0; k < int(c.size()); ++k) {
        if (!out.empty() && c[out.back()].primitive == c[k].primitive) {
            if (c[k].distance < c[out.back()].distance) out.back() = k;
        } else {
            out.push_back(k);
        }
    }
    return out;
}

} // namespace

GroupPlaneAlgorithm::GroupPlaneAlgorithm(const btCollisionAlgorithmConstructionInfo& ci,
                                         const btCollisionObjectWrapper* body0, const btCollisionObjectWrapper* body1,
                                         bool groupIsBody0)
    : GroupVersusAlgorithm(ci, body0, body1, groupIsBody0),
      manifold_(m_dispatcher->getNewManifold(body0->getCollisionObject(), body1->getCollisionObject())) {}

GroupPlaneAlgorithm::~GroupPlaneAlgorithm() { m_dispatcher->releaseManifold(manifold_); }

void GroupPlaneAlgorithm::getAllContactManifolds(btManifoldArray& manifolds) {
    manifolds.push_back(manifold_);
    leaves_.appendManifolds(manifolds);
}

void GroupPlaneAlgorithm::processCollision(const btCollisionObjectWrapper* body0,
                                           const btCollisionObjectWrapper* body1, const btDispatcherInfo&,
                                           btManifoldResult* result) {
    const auto [groupWrap, planeWrap] = sides(body0, body1);
    const GroupShape& group = groupOf(groupWrap);
    followRenumbering(group);
    const auto* plane = static_cast<const btStaticPlaneShape*>(planeWrap->getCollisionShape());
    const btTransform& groupToWorld = groupWrap->getWorldTransform();
    const btTransform& planeToWorld = planeWrap->getWorldTransform();

    // The plane in group coordinates: n·x = offset.
    const btVector3 normalWorld = planeToWorld.getBasis() * plane->getPlaneNormal();
    const btVector3 pointWorld = planeToWorld * (plane->getPlaneNormal() * plane->getPlaneConstant());
    const Eigen::Vector3d n = toEigen(groupToWorld.getBasis().transpose() * normalWorld).normalized();
    const double offset = n.dot(toEigen(groupToWorld.invXform(pointWorld)));
    const double margin = double(group.getMargin());
    const double reach = double(manifold_->getContactBreakingThreshold()) + double(result->m_closestPointDistanceThreshold);

    candidates_.clear();
    struct Collect {
        const GroupShape& group;
        const Eigen::Vector3d& n;
        double offset, margin, reach;
        std::vector<Candidate>& out;
        void operator()(int i) const {
            const auto& vertices = group.primitives()[i].vertices();
            for (int v = 0; v < int(vertices.size()); ++v) {
                const double distance = n.dot(vertices[v]) - offset - margin;
                if (distance < reach) out.push_back({vertices[v], distance, i, v});
            }
        }
    };
    const Collect collect{group, n, offset, margin, reach, candidates_};
    group.tree().queryBelowPlane(n, offset + margin + reach, [&collect](int i) { collect(i); });

    // A group whose primitives move on their own gives each primitive its own manifold (one
    // shared manifold keeps only 4 points); a rigid group keeps its 4 support points in one.
    const bool perPrimitive = group.contactPerPrimitive();
    std::vector<int> chosen(4);
    if (perPrimitive) chosen = deepestPerPrimitive(candidates_);
    else chosen.resize(selectSupport(carryingFirst(candidates_, 0.1 * reach), n, 0.05 * reach, chosen.data()));
    if (perPrimitive) leaves_.begin();
    else result->setPersistentManifold(manifold_);
    for (int index : chosen) {
        const Candidate& c = candidates_[index];
        if (perPrimitive) {
            LeafCache::Entry& entry = leaves_.touch(std::uint64_t(c.primitive));
            if (!entry.manifold)
                entry.manifold = m_dispatcher->getNewManifold(body0->getCollisionObject(), body1->getCollisionObject());
            result->setPersistentManifold(entry.manifold);
        }
        const btVector3 onGroup = groupToWorld * toBullet(c.vertex) - normalWorld * btScalar(margin);
        const btVector3 onPlane = onGroup - normalWorld * btScalar(c.distance);
        const btCollisionObjectWrapper child(groupWrap, &group.child(c.primitive), groupWrap->getCollisionObject(),
                                             groupToWorld, -1, c.primitive);
        const LeafScope scope(result, groupIsBody0_ ? &child : planeWrap, groupIsBody0_ ? planeWrap : &child);
        // Bullet's normal points from body1 to body0; the point given lies on body1.
        if (groupIsBody0_)
            result->addContactPoint(normalWorld, onPlane, btScalar(c.distance));
        else
            result->addContactPoint(-normalWorld, onGroup, btScalar(c.distance));
        if (perPrimitive) result->refreshContactPoints();
    }
    if (perPrimitive) leaves_.end();
    else result->refreshContactPoints();
}

// ---------------------------------------------------------------------------------------

namespace {

// Collects (triangle, primitive) pairs: every primitive near each triangle Bullet reports.
class TriangleCollector : public btTriangleCallback {
public:
    TriangleCollector(const GroupShape& group, const btTransform& concaveToGroup, double grow,
                      std::vector<GroupConcaveAlgorithm::TriangleHit>& hits)
        : group_(group), concaveToGroup_(concaveToGroup), grow_(grow), hits_(hits) {}

    void processTriangle(btVector3* triangle, int partId, int triangleIndex) override {
        btVector3 min = concaveToGroup_ * triangle[0], max = min;
        for (int k = 1; k < 3; ++k) {
            const btVector3 p = concaveToGroup_ * triangle[k];
            min.setMin(p);
            max.setMax(p);
        }
        current_ = {{triangle[0], triangle[1], triangle[2]}, partId, triangleIndex, -1, 0};
        group_.tree().query(grownBox(min, max, grow_), [this](int i) {
            current_.primitive = i;
            current_.sequence = int(hits_.size());
            hits_.push_back(current_);
        });
    }

private:
    const GroupShape& group_;
    btTransform concaveToGroup_;
    double grow_;
    std::vector<GroupConcaveAlgorithm::TriangleHit>& hits_;
    GroupConcaveAlgorithm::TriangleHit current_{};
};

// One primitive against the triangles near it, into that primitive's manifold. Triangles keep
// Bullet's default path (GJK on the margin-grown shapes), as in Bullet's own convex-concave
// algorithm: its separating-axis branch for triangles exists only with the hull as the first
// argument, so turning it on would make the rest height depend on the broadphase order.
struct TriangleRun {
    btDispatcher* dispatcher;
    const btCollisionObjectWrapper* child;
    const btCollisionObjectWrapper* concaveWrap;
    bool groupIsBody0;
    btScalar triangleMargin;
    btPersistentManifold* manifold;
    const btDispatcherInfo& info;
    btManifoldResult* result;

    void operator()(const GroupConcaveAlgorithm::TriangleHit& hit) const {
        btTriangleShape triangle(hit.vertices[0], hit.vertices[1], hit.vertices[2]);
        triangle.setMargin(triangleMargin);
        const btCollisionObjectWrapper triangleWrap(concaveWrap, &triangle, concaveWrap->getCollisionObject(),
                                                    concaveWrap->getWorldTransform(), hit.partId, hit.triangleIndex);
        const btCollisionObjectWrapper* a = groupIsBody0 ? child : &triangleWrap;
        const btCollisionObjectWrapper* b = groupIsBody0 ? &triangleWrap : child;
        btCollisionAlgorithm* algorithm = dispatcher->findAlgorithm(a, b, manifold, leafQuery(result));
        if (!algorithm) return;
        result->setPersistentManifold(manifold);
        {
            const LeafScope scope(result, a, b);
            algorithm->processCollision(a, b, info, result);
        }
        algorithm->~btCollisionAlgorithm();
        dispatcher->freeCollisionAlgorithm(algorithm);
    }
};

} // namespace

void GroupConcaveAlgorithm::processCollision(const btCollisionObjectWrapper* body0,
                                             const btCollisionObjectWrapper* body1, const btDispatcherInfo& info,
                                             btManifoldResult* result) {
    const auto [groupWrap, concaveWrap] = sides(body0, body1);
    const GroupShape& group = groupOf(groupWrap);
    followRenumbering(group);
    const auto* concave = static_cast<const btConcaveShape*>(concaveWrap->getCollisionShape());
    const btScalar triangleMargin = concave->getMargin();
    const double reach = contactDistance(m_dispatcher, body0, body1, result);

    // Gather first, then run primitive by primitive: each primitive's manifold is touched
    // once per step, whatever order the concave shape reports its triangles in.
    hits_.clear();
    const btTransform concaveToGroup = groupWrap->getWorldTransform().inverseTimes(concaveWrap->getWorldTransform());
    TriangleCollector collector(group, concaveToGroup, double(group.getMargin()) + double(triangleMargin) + reach, hits_);
    btVector3 min, max;
    group.getAabb(concaveToGroup.inverse(), min, max);
    const btVector3 grow(btScalar(triangleMargin + reach), btScalar(triangleMargin + reach), btScalar(triangleMargin + reach));
    concave->processAllTriangles(&collector, min - grow, max + grow);
    std::sort(hits_.begin(), hits_.end(), [](const TriangleHit& a, const TriangleHit& b) {
        return a.primitive != b.primitive ? a.primitive < b.primitive : a.sequence < b.sequence;
    });

    leaves_.begin();
    for (size_t first = 0, last = 0; first < hits_.size(); first = last) {
        const int primitive = hits_[first].primitive;
        while (last < hits_.size() && hits_[last].primitive == primitive) ++last;
        LeafCache::Entry& entry = leaves_.touch(std::uint64_t(primitive));
        if (!entry.manifold)
            entry.manifold = m_dispatcher->getNewManifold(body0->getCollisionObject(), body1->getCollisionObject());
        const btCollisionObjectWrapper child(groupWrap, &group.child(primitive), groupWrap->getCollisionObject(),
                                             groupWrap->getWorldTransform(), -1, primitive);
        const TriangleRun run{m_dispatcher, &child, concaveWrap, groupIsBody0_, triangleMargin, entry.manifold, info, result};
        for (size_t k = first; k < last; ++k) run(hits_[k]);
        result->setPersistentManifold(entry.manifold);
        result->refreshContactPoints();
    }
    leaves_.end();
}

// ---------------------------------------------------------------------------------------
void GroupGroupAlgorithm::recordPose(const btTransform& bToA, const btTransform& aToB) {
    ++step_;
    PoseAt& now = poses_[step_ % kPoses];
    now.step = step_;
    now.r = toEigen(bToA.getBasis());
    now.p = toEigen(bToA.getOrigin());
    now.q = toEigen(aToB.getOrigin());
    originReach_ = std::max(now.p.norm(), now.q.norm());
    for (std::uint32_t k = 0; k < kPoses; ++k) {
        const PoseAt& was = poses_[k]; // the pose of the latest step ≡ k (mod kPoses), up to this one
        MotionSince& m = motion_[k];
        m.known = was.step >= provenFrom_ && was.step > 0;
        if (!m.known) continue;
        m.dr = now.r - was.r;
        m.dp = now.p - was.p;
        m.dq = now.q - was.q;
        m.drNorm = m.dr.norm();
    }
}

bool GroupGroupAlgorithm::provenApart(const LeafCache::Entry& entry) const {
    const ApartProof& proof = entry.apart;
    if (proof.budget < 0 || step_ - proof.step >= kPoses || entry.algorithm) return false;
    const MotionSince& m = motion_[proof.step % kPoses];
    if (!m.known) return false;
    if (entry.manifold && entry.manifold->getNumContacts() > 0) return false;
    // Every vertex x of the other hull (within radius of centre, its body's frame) moved, seen
    // from the face's body, by |dr x + dt| <= |dr centre + dt| + |dr|·radius: for a face of a
    // (body0's) the other hull is body1's, placed by bToA = (r, p); for a face of b, body0's,
    // placed by aToB = (rᵀ, q). The face's normal is a unit vector to float rounding.
    const Eigen::Vector3d c(proof.centre[0], proof.centre[1], proof.centre[2]);
    const Eigen::Vector3d shift =
        proof.onB ? Eigen::Vector3d(m.dr.transpose() * c + m.dq) : Eigen::Vector3d(m.dr * c + m.dp);
    const double moved = shift.norm() + m.drNorm * double(proof.radius);
    return moved * (1 + kRoundingPerMetre) + kRoundingPerMetre * originReach_ < double(proof.budget);
}

bool GroupGroupAlgorithm::listStillHolds(const Eigen::Isometry3d& oneToZero, double reach, const GroupShape& g0,
                                         const GroupShape& g1) const {
    if (listReach_ < 0 || g0.revision() != listedRevision0_ || g1.revision() != listedRevision1_) return false;
    // How far the bodies moved relative to each other since the list was made bounds how much
    // closer any primitive pair came (HullPairContacts::pairListSlack says where the box test
    // can ask for more): the motion of body1's points seen from body0, or of body0's seen
    // from body1, whichever bound is smaller. Measured only from body1, a small
    // fragment turning beside a large body would turn by the large body's radius and ask for a
    // new list (a walk of the large body's tree) almost every step: the 55,411-tet statue hit
    // by the wall's ball, 460 of 1,042 checks in 30 frames, against 25 with the smaller bound.
    const double moved1 = motionBound(listedAt_.inverse() * oneToZero, g1.tree().bounds());
    const double moved0 = motionBound(oneToZero * listedAt_.inverse(), g0.tree().bounds());
    return reach + std::min(moved0, moved1) <= listReach_;
}

GroupGroupAlgorithm::GroupGroupAlgorithm(const btCollisionAlgorithmConstructionInfo& ci,
                                         const btCollisionObjectWrapper* body0, const btCollisionObjectWrapper* body1)
    : GroupAlgorithmBase(ci, body0, body1) {}

GroupGroupAlgorithm::~GroupGroupAlgorithm() {
    for (Listed& p : listed_) leave(p.entry);
    LeafCache::releaseInKeyOrder(m_dispatcher, leaving_);
}

void GroupGroupAlgorithm::leave(LeafCache::Entry& entry) {
    if (!entry.held()) return;
    leaving_.push_back(entry);
    entry.forget();
}

void GroupGroupAlgorithm::followRenumbering(const GroupShape& g0, const GroupShape& g1) {
    if (!seen_) {
        // A new pair lists nothing yet: it starts from the groups as they are, not from revision
        // 0, whose map (a copy of the whole removal chain) Spot's statue paid at every new pair.
        listedRevision0_ = g0.revision();
        listedRevision1_ = g1.revision();
        seen_ = true;
        return;
    }
    SeenRevision seen0{listedRevision0_}, seen1{listedRevision1_};
    const std::optional<std::vector<int>> to0 = seen0.update(g0), to1 = seen1.update(g1);
    if (!to0 && !to1) return; // the same primitives (perhaps moved: the list is made anew by key)
    leaves_.renumber({}); // a closest-points query's leaves, keyed by pair: made anew
    if ((to0 && to0->empty()) || (to1 && to1->empty())) {
        for (Listed& p : listed_) leave(p.entry);
        listed_.clear();
        listReach_ = -1.0;
        return;
    }
    std::size_t kept = 0;
    for (Listed& p : listed_) {
        const int i = to0 ? (*to0)[size_t(p.i)] : p.i;
        const int j = to1 ? (*to1)[size_t(p.j)] : p.j;
        if (i < 0 || j < 0) {
            leave(p.entry); // its points went with the edit: an empty manifold, freed at the step's end
            continue;
        }
        Listed& q = listed_[kept++];
        q.entry = p.entry;
        q.entry.key = pairKey(i, j);
        q.i = i;
        q.j = j;
    }
    listed_.erase(listed_.begin() + std::ptrdiff_t(kept), listed_.end());
    // A side only renumbered is where it was; one that moved (a soft step) keeps its old
    // revision, so the list is made anew.
    if (to0) listedRevision0_ = g0.revision();
    if (to1) listedRevision1_ = g1.revision();
}

void GroupGroupAlgorithm::getAllContactManifolds(btManifoldArray& manifolds) {
    GroupAlgorithmBase::getAllContactManifolds(manifolds);
    for (const Listed& p : listed_) LeafCache::appendManifolds(p.entry, manifolds);
}

void GroupGroupAlgorithm::relist(const GroupShape& g0, const GroupShape& g1, const Eigen::Isometry3d& oneToZero,
                                 double listReach, double reach) {
    // The old list's entries by key (key and place only: an entry is a hundred bytes).
    oldList_.swap(listed_);
    listed_.clear();
    reachedNow_.clear();
    oldKeys_.clear();
    for (std::uint32_t k = 0; k < oldList_.size(); ++k)
        if (oldList_[k].entry.held()) oldKeys_.emplace_back(oldList_[k].entry.key, k);
    std::sort(oldKeys_.begin(), oldKeys_.end());
    const BoxTurn turn(oneToZero);
    NearBoxes near(g1, turn, listReach); // j's turned box made once per relist, not once per pair
    // The contact trees' boxes are grown by the groups' contact slacks (1 cm each), the list
    // needs listReach (6 mm on the table): node pairs that overlap by less than relistDepth
    // hold no pair the box test below keeps, and are not walked (unless pruneRelist is off).
    // The walk then visits some of the pairs it visited unpruned, in the same order, so the
    // list is the same.
    const Eigen::Vector3d depth = hullPairContacts().pruneRelist
                                      ? relistDepth(oneToZero.linear(), g0.contactSlack(), g1.contactSlack(), listReach)
                                      : Eigen::Vector3d::Zero();
    g0.contactTree().pairsWith(g1.contactTree(), oneToZero, [&](int i, int j) {
        // Within the list's reach (listed), and within the contact reach (run this step): one
        // pass of the box test gives both (the step's loop asked again, pair by pair, for a
        // third of the table's group pairs' instructions in its split frames).
        const int within = near[j].withinBoth(g0.primitives()[i].bounds(), reach);
        if (within == 0) return;
        reachedNow_.push_back(within == 2);
        const std::uint64_t key = pairKey(i, j);
        const auto it = std::lower_bound(oldKeys_.begin(), oldKeys_.end(), std::pair<std::uint64_t, std::uint32_t>(key, 0));
        if (it != oldKeys_.end() && it->first == key) {
            LeafCache::Entry& old = oldList_[it->second].entry;
            listed_.push_back({i, j, old});
            old.forget(); // moved into the new list
        } else {
            listed_.push_back({i, j, LeafCache::Entry{key}});
        }
    }, depth);
    // The rest leave at the step's end, with the pairs the step does not reach.
    for (Listed& p : oldList_) leave(p.entry);
    oldList_.clear();
}

void GroupGroupAlgorithm::processCollision(const btCollisionObjectWrapper* body0,
                                           const btCollisionObjectWrapper* body1, const btDispatcherInfo& info,
                                           btManifoldResult* result) {
    const GroupShape& g0 = groupOf(body0);
    const GroupShape& g1 = groupOf(body1);
    followRenumbering(g0, g1);
    const Eigen::Isometry3d oneToZero = toEigen(body0->getWorldTransform().inverseTimes(body1->getWorldTransform()));

    // Runs the pair (i, j) with `entry` if it is within the reach; false (nothing run) if not.
    struct Visit {
        btDispatcher* dispatcher;
        const btCollisionObjectWrapper* body0;
        const btCollisionObjectWrapper* body1;
        const btDispatcherInfo& info;
        btManifoldResult* result;
        const BoxTurn& turn;
        double slack;
        const LeafPoses& poses; // the leaves' transforms are their bodies'

        bool near(int i, int j) const {
            return boxesWithin(groupOf(body0).primitives()[i].bounds(), groupOf(body1).primitives()[j].bounds(), turn, slack);
        }
        // The same answer from j's box made once for the step (after relist, whose boxes share the scratch).
        bool near(int i, int j, NearBoxes& boxes) const { return boxes[j].within(groupOf(body0).primitives()[i].bounds()); }
        void operator()(int i, int j, LeafCache::Entry& entry) const {
            const btCollisionObjectWrapper a(body0, &groupOf(body0).child(i), body0->getCollisionObject(),
                                             body0->getWorldTransform(), -1, i);
            const btCollisionObjectWrapper b(body1, &groupOf(body1).child(j), body1->getCollisionObject(),
                                             body1->getWorldTransform(), -1, j);
            runLeaf(entry, dispatcher, &a, &b, false, info, result, &poses); // leaves of two groups
        }
    };
    const bool query = result->m_closestPointDistanceThreshold > 0;
    // Contacts: hull pairs make points only where the hulls overlap (separating-axis path),
    // so pairs within the breaking threshold are enough. A closest-points query (GJK path)
    // reports distances between the margin-grown hulls, up to the distance it asks for.
    const double reach = contactDistance(m_dispatcher, body0, body1, result) +
                         (query ? double(g0.getMargin()) + double(g1.getMargin()) : 0.0);
    const BoxTurn turn(oneToZero);

    leaves_.begin();
    // The two groups' whole oriented boxes apart by more than the reach: no primitive pair
    // can come within it. Bullet pairs the bodies by world boxes grown by its tree margin, so in
    // a heap most group pairs are such, and the trees' walk (by axis-aligned boxes of turned
    // boxes, up to 1.7 times larger) finds that out node by node. Leaves kept from the last
    // step go (end() frees what was not touched), and nothing the leaves share is made.
    if (!boxesWithin(g0.tree().bounds(), g1.tree().bounds(), turn, reach)) {
        for (Listed& p : listed_) leave(p.entry);
        leaves_.end();
        LeafCache::releaseInKeyOrder(m_dispatcher, leaving_);
        return;
    }
    if (!query) {
        // Proofs made before a group changed (its primitives renumbered, replaced or moved) are void.
        if (g0.revision() != provenRevision0_ || g1.revision() != provenRevision1_) provenFrom_ = step_ + 1;
        provenRevision0_ = g0.revision();
        provenRevision1_ = g1.revision();
    }
    // The scale of the coordinates the leaves' tests compute with: the bodies' distances from
    // the world origin and the groups' reach from their own origins, each counted twice (a
    // hull's vertices, a plane's offset, the turned offset between the bodies).
    const double roundingScale =
        2 * (double(body0->getWorldTransform().getOrigin().length()) +
             double(body1->getWorldTransform().getOrigin().length()) + boxReach(g0.tree().bounds()) +
             boxReach(g1.tree().bounds()));
    // No proofs on a step that voided them (a group changed): a group whose revision changes
    // every step (a soft group's setPrimitivePoses) would void them all the next step, so
    // making them is pure cost. After a one-off change the pairs are proven a step later.
    const bool proving = !query && provenFrom_ <= step_;
    const LeafPoses poses(body0->getWorldTransform(), body1->getWorldTransform(), proving ? step_ + 1 : 0,
                          query ? 0.0 : roundingScale);
    if (!query) recordPose(poses.pose.bToA, poses.pose.aToB);
    const btDispatcherInfo leaf = leafInfo(info, result);
    const Visit visit{m_dispatcher, body0, body1, leaf, result, turn, reach, poses};
    if (query) {
        // The query may reach farther than the contact trees were grown: go primitive by
        // primitive (queries are rare; the per-step path below is the pair of trees).
        const double grow = reach;
        for (int j = 0; j < g1.primitiveCount(); ++j) {
            const geometry::Aabb box = geometry::transformedAabb(g1.primitives()[j].bounds(), oneToZero).inflated(grow);
            g0.tree().query(box, [&](int i) {
                if (visit.near(i, j)) visit(i, j, leaves_.touch(pairKey(i, j)));
            });
        }
    } else {
        // A pair within the reach now was within reach + the motion since the list was made, so
        // the list holds it while that motion stays within the slack. The contact trees report
        // every pair within their two growths, which bounds the slack. Without slack the list
        // is made anew every step: the pairs within the reach, in the trees' walk order.
        const double slack =
            std::min(hullPairContacts().pairListSlack, g0.contactSlack() + g1.contactSlack() - reach);
        const bool relisted = slack <= 0 || !listStillHolds(oneToZero, reach, g0, g1);
        if (relisted) {
            relist(g0, g1, oneToZero, reach + std::max(slack, 0.0), reach);
            listedAt_ = oneToZero;
            listReach_ = slack > 0 ? reach + slack : -1.0;
            listedRevision0_ = g0.revision();
            listedRevision1_ = g1.revision();
        }
        NearBoxes boxes(g1, turn, reach);
        const bool skip = hullPairContacts().skipProvenApart;
        for (std::size_t k = 0; k < listed_.size(); ++k) {
            Listed& p = listed_[k];
            if (!(relisted ? bool(reachedNow_[k]) : visit.near(p.i, p.j, boxes))) {
                leave(p.entry); // not reached: it goes, as the cache's end() frees it
            } else if (skip && provenApart(p.entry)) {
                ++skippedAsApart; // its run would find its face and leave its empty manifold as it is
            } else {
                visit(p.i, p.j, p.entry);
            }
        }
    }
    leaves_.end();
    LeafCache::releaseInKeyOrder(m_dispatcher, leaving_);
}

// ---------------------------------------------------------------------------------------
namespace {

bool isGroup(const btCollisionShape* shape) {
    return shape->getShapeType() == kGroupShapeType && dynamic_cast<const GroupShape*>(shape) != nullptr;
}

// Our algorithms may outgrow the dispatcher's pool elements (sized for Bullet's own);
// freeCollisionAlgorithm tells pool memory from heap memory by address, so both are fine.
template <class Algorithm, class... Args>
btCollisionAlgorithm* create(btCollisionAlgorithmConstructionInfo& ci, Args&&... args) {
    auto* dispatcher = static_cast<btCollisionDispatcher*>(ci.m_dispatcher1);
    const int size = int(sizeof(Algorithm));
    void* memory = size <= dispatcher->getCollisionConfiguration()->getCollisionAlgorithmPool()->getElementSize()
                       ? dispatcher->allocateCollisionAlgorithm(size)
                       : btAlignedAlloc(size_t(size), 16);
    return new (memory) Algorithm(ci, std::forward<Args>(args)...);
}

btCollisionAlgorithmCreateFunc* configurationFunc(btCollisionDispatcher& dispatcher, ebtDispatcherQueryType type,
                                                  int type0, int type1) {
    btCollisionConfiguration* config = dispatcher.getCollisionConfiguration();
    return type == BT_CLOSEST_POINT_ALGORITHMS ? config->getClosestPointsAlgorithmCreateFunc(type0, type1)
                                               : config->getCollisionAlgorithmCreateFunc(type0, type1);
}

// Compound shapes keep Bullet's compound algorithm, which dispatches each child against the
// group back to us; soft bodies have their own pipeline.
bool registered(int type) { return type != COMPOUND_SHAPE_PROXYTYPE && type != SOFTBODY_SHAPE_PROXYTYPE; }

} // namespace

btCollisionAlgorithm* GroupAlgorithmCreateFunc::CreateCollisionAlgorithm(btCollisionAlgorithmConstructionInfo& ci,
                                                                         const btCollisionObjectWrapper* body0,
                                                                         const btCollisionObjectWrapper* body1) {
    const btCollisionShape* shape0 = body0->getCollisionShape();
    const btCollisionShape* shape1 = body1->getCollisionShape();
    const bool group0 = isGroup(shape0);
    const bool group1 = isGroup(shape1);
    if (group0 && group1) return create<GroupGroupAlgorithm>(ci, body0, body1);
    const btCollisionShape* other = group0 ? shape1 : shape0;
    if (group0 || group1) {
        if (other->getShapeType() == STATIC_PLANE_PROXYTYPE) return create<GroupPlaneAlgorithm>(ci, body0, body1, group0);
        if (other->isConvex()) return create<GroupConvexAlgorithm>(ci, body0, body1, group0);
        if (other->isConcave()) return create<GroupConcaveAlgorithm>(ci, body0, body1, group0);
    }
    auto* dispatcher = static_cast<btCollisionDispatcher*>(ci.m_dispatcher1);
    return configurationFunc(*dispatcher, queryType_, shape0->getShapeType(), shape1->getShapeType())
        ->CreateCollisionAlgorithm(ci, body0, body1);
}

std::uint64_t provenApartSkips() { return skippedAsApart; }

void registerGroupShapeAlgorithms(btCollisionDispatcher& dispatcher) {
    // Never destroyed: a dispatcher that outlives static destruction may still call them.
    static auto* const contact = new GroupAlgorithmCreateFunc(BT_CONTACT_POINT_ALGORITHMS);
    static auto* const closest = new GroupAlgorithmCreateFunc(BT_CLOSEST_POINT_ALGORITHMS);
    static auto* const fragments = new FragmentPairCreateFunc;
    dispatcher.registerCollisionCreateFunc(CONVEX_HULL_SHAPE_PROXYTYPE, CONVEX_HULL_SHAPE_PROXYTYPE, fragments);
    for (int t = 0; t < MAX_BROADPHASE_COLLISION_TYPES; ++t) {
        if (!registered(t)) continue;
        dispatcher.registerCollisionCreateFunc(kGroupShapeType, t, contact);
        dispatcher.registerCollisionCreateFunc(t, kGroupShapeType, contact);
        dispatcher.registerClosestPointsCreateFunc(kGroupShapeType, t, closest);
        dispatcher.registerClosestPointsCreateFunc(t, kGroupShapeType, closest);
    }
}

void unregisterGroupShapeAlgorithms(btCollisionDispatcher& dispatcher) {
    dispatcher.registerCollisionCreateFunc(
        CONVEX_HULL_SHAPE_PROXYTYPE, CONVEX_HULL_SHAPE_PROXYTYPE,
        configurationFunc(dispatcher, BT_CONTACT_POINT_ALGORITHMS, CONVEX_HULL_SHAPE_PROXYTYPE, CONVEX_HULL_SHAPE_PROXYTYPE));
    for (int t = 0; t < MAX_BROADPHASE_COLLISION_TYPES; ++t) {
        if (!registered(t)) continue;
        for (const auto& [a, b] : {std::pair{kGroupShapeType, t}, std::pair{t, kGroupShapeType}}) {
            dispatcher.registerCollisionCreateFunc(a, b, configurationFunc(dispatcher, BT_CONTACT_POINT_ALGORITHMS, a, b));
            dispatcher.registerClosestPointsCreateFunc(a, b,
                                                       configurationFunc(dispatcher, BT_CLOSEST_POINT_ALGORITHMS, a, b));
        }
    }
}

} // namespace shatter
