#pragma once
// Bullet collision algorithms for the group shape (GroupShape.h). They run Bullet's own
// algorithms on the primitive pairs the bounding-volume tree reports, so the cost per step
// follows the primitives near the contact, never the primitive count.
// registerGroupShapeAlgorithms() puts them in a dispatcher; the classes are public for tests
// and for applications that build their own dispatch tables.
//
// Manifolds: every primitive (or primitive pair) near the other body has its own persistent
// manifold, kept while it stays near, as every child of Bullet's btCompoundShape has. One
// manifold shared by all primitives keeps only 4 of their points and, being full, replaces
// one every step, which throws away the solver's warm start: a table resting on a group floor
// then jitters (velocity spikes of 2 cm/s over 1000 steps, against 0.25 mm/s with one manifold
// per primitive). The static plane is the exception: its algorithm picks 4 support points
// itself, the same ones from step to step, and a body on a plane rests still to 1e-6 m/s.
//
// Hull-hull leaf pairs run with Bullet's separating-axis test on (see leafInfo in the .cpp):
// exact face normals, and contact only where the hulls overlap, so such pairs rest solid on
// solid; so do a group's hulls on a btBoxShape (HullPairContacts::boxLeavesClipped); pairs
// with a sphere, capsule, triangle or plane rest a margin apart, as in Bullet.
#include <shatter/bullet_ext/shape/GroupShape.h>
#include <shatter/bullet_ext/shape/HullPairContacts.h>

#include <BulletCollision/BroadphaseCollision/btDispatcher.h>
#include <BulletCollision/CollisionDispatch/btActivatingCollisionAlgorithm.h>
#include <BulletCollision/CollisionDispatch/btCollisionCreateFunc.h>
#include <BulletCollision/CollisionShapes/btConvexPolyhedron.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <utility>
#include <vector>

namespace shatter {

// A hull pair found apart by a face plane (separatingFace): the nearest vertex of the other
// hull lay `budget` (m) in front of the face, less a margin for the test's float rounding, when
// the group pair made its step `step`. The other hull's vertices lie within `radius` of
// `centre` (its body's frame). While they have moved less than the budget relative to the
// face since then, the face still separates the pair as the test computes it.
// (The step first: 32 bytes with its 64 bits, and LeafCache::Entry keeps main's 136.)
struct ApartProof {
    std::uint64_t step = 0; // 64 bits: a step count never wraps into a stale proof
    float centre[3] = {0, 0, 0};
    float radius = 0;
    float budget = -1; // < 0: no proof
    bool onB = false; // the face is body1's primitive's (the other hull body0's)
};

// The leaf pairs (a primitive, or a pair of primitives, against something) that were near in
// the last step, each with its child algorithm or manifold, sorted by key. A step calls
// begin(), touch() once for each key it meets (never twice), then end(), which frees the
// entries it did not meet. No allocation once warm.
class LeafCache {
public:
    struct Entry {
        std::uint64_t key;
        btCollisionAlgorithm* algorithm = nullptr; // owns its manifold, or
        btPersistentManifold* manifold = nullptr;  // a manifold the group algorithm fills itself
        int separatingFace = -1; // hull pairs: the face that kept them apart last step, or -1
        int separatingAxis = -1; // hull pairs: the axis that last separated them (polyhedronContacts), or -1
        // Group-group hull pairs with an empty manifold: proof that face separatingFace keeps
        // them apart while the bodies move little (GroupGroupAlgorithm::provenApart). Before
        // lastClip, so that the 8-byte-aligned proof needs no padding.
        ApartProof apart{};
        LastClip lastClip{};     // hull pairs: where they stood at their last clip
        // A hull pair that has had its first run: with HullPairContacts::keepEmptyLeafManifolds
        // off, in a world that takes its contacts in the own order (dispatcherOrdersContacts),
        // its manifold exists only while it holds points, so the manifold no longer says so.
        bool seen = false;
        // Something to keep between steps (or to free): a child, a manifold, or a first run.
        bool held() const { return algorithm || manifold || seen; }
        // Forgets the pair (after freeing): its next run is a first run.
        void forget() { *this = Entry{key}; }
    };

    explicit LeafCache(btDispatcher* dispatcher) : dispatcher_(dispatcher) {}
    ~LeafCache();
    LeafCache(const LeafCache&) = delete;
    LeafCache& operator=(const LeafCache&) = delete;

    void begin() { next_.clear(); }
    // Last step's entry for `key`, or a new empty one (algorithm and manifold null). The
    // reference is valid until the next touch().
    Entry& touch(std::uint64_t key);
    // Frees what the step did not touch.
    void end();
    // The leaves' manifolds that hold points. Bullet's callers (the compound algorithms' refresh
    // of their children's points, a character controller's recovery) look only at points, and
    // the empty ones can be tens of thousands: between the table's two broken halves, ~39,000
    // a step, which btCompoundCompoundCollisionAlgorithm gathered into a fresh array every
    // step only to skip (frames 92-97: 102 M of 1,129 M instructions; left out here, 27 M
    // less, as each manifold's count is still read). All of them stay in the dispatcher, where
    // the solver and the contact snapshot take them.
    void appendManifolds(btManifoldArray& manifolds) const;
    // Between steps, after the group's primitives were renumbered with the body in the world
    // (GroupShape::indexMapFrom): an entry keyed by primitive k is now keyed by to[k], and freed
    // (in key order) if to[k] < 0. Empty `to`: the map is not known, and every entry is freed.
    void renumber(std::span<const int> to);
    // Frees an entry's algorithm and manifold (null after).
    static void release(btDispatcher* dispatcher, Entry& e);
    // Frees the entries in key order, as end() frees what a step did not touch: Bullet fills a
    // released manifold's place with its last one, and its solver takes the manifolds in that
    // order, so the order of release is part of the physics.
    static void releaseInKeyOrder(btDispatcher* dispatcher, std::vector<Entry>& entries);
    static void appendManifolds(const Entry& e, btManifoldArray& manifolds);

private:
    btDispatcher* dispatcher_;
    std::vector<Entry> current_; // sorted by key
    std::vector<Entry> next_;    // in the order this step touched them
};

// What every group algorithm shares: the leaf cache, and no continuous collision of its own.
class GroupAlgorithmBase : public btActivatingCollisionAlgorithm {
public:
    GroupAlgorithmBase(const btCollisionAlgorithmConstructionInfo& ci, const btCollisionObjectWrapper* body0,
                       const btCollisionObjectWrapper* body1);

    // Continuous collision goes through Bullet's sweep tests (processAllTriangles), not here.
    btScalar calculateTimeOfImpact(btCollisionObject*, btCollisionObject*, const btDispatcherInfo&,
                                   btManifoldResult*) override {
        return btScalar(1);
    }
    // The manifolds that hold points (LeafCache::appendManifolds); empty ones are left out.
    void getAllContactManifolds(btManifoldArray& manifolds) override;

protected:
    LeafCache leaves_;
};

// The revision of a group shape an algorithm last saw, and what became of its primitives since
// (GroupShape::indexMapFrom): what keeps a pair's leaves across a shrink of the group with the
// body in the world (LatticeSettings::keepPairsOnShrink).
struct SeenRevision {
    std::uint64_t revision;
    // Primitives removed or replaced since: their map (the numbering then to now, −1 removed), or
    // none, an empty map (the leaves must all go). Null when no index changed (nothing, or a soft
    // step moved the primitives). Then sees the shape's revision now.
    std::optional<std::vector<int>> update(const GroupShape& group);
};

// A group against another kind of shape: which of the pair's bodies is the group.
class GroupVersusAlgorithm : public GroupAlgorithmBase {
public:
    GroupVersusAlgorithm(const btCollisionAlgorithmConstructionInfo& ci, const btCollisionObjectWrapper* body0,
                         const btCollisionObjectWrapper* body1, bool groupIsBody0)
        : GroupAlgorithmBase(ci, body0, body1), groupIsBody0_(groupIsBody0) {}

protected:
    // The group's wrapper and the other body's, from the pair's (body0, body1).
    struct Sides {
        const btCollisionObjectWrapper* group;
        const btCollisionObjectWrapper* other;
    };
    Sides sides(const btCollisionObjectWrapper* body0, const btCollisionObjectWrapper* body1) const {
        return groupIsBody0_ ? Sides{body0, body1} : Sides{body1, body0};
    }
    // The leaves follow the group's primitives renumbered since the last step (SeenRevision).
    void followRenumbering(const GroupShape& group);
    bool groupIsBody0_;
    std::optional<SeenRevision> seen_; // from the first step on
};

// Group against any convex shape (box, sphere, capsule, hull, triangle, ...): the tree is
// queried with the other shape's box in group coordinates; one child algorithm per primitive.
// Against a btBoxShape, each primitive's manifold may be filled here instead
// (PolyhedronContacts.h): for a rigid group (HullPairContacts::boxLeavesClipped), the box as a
// polyhedron, the separating-axis test and face clipping, as for two hulls; for a group with
// one contact per primitive (a soft body, HullPairContacts::softBoxContacts), GJK's one point
// a step from a separating-axis test in the box's frame.
class GroupConvexAlgorithm : public GroupVersusAlgorithm {
public:
    using GroupVersusAlgorithm::GroupVersusAlgorithm;
    void processCollision(const btCollisionObjectWrapper* body0, const btCollisionObjectWrapper* body1,
                          const btDispatcherInfo& info, btManifoldResult* result) override;

private:
    // The other body's btBoxShape as a polyhedron (its half extents with the margin: the
    // box's surface), remade when those change.
    const btConvexPolyhedron& boxFeatures(const btVector3& halfExtents);
    std::unique_ptr<btConvexPolyhedron> box_;
    btVector3 boxHalf_{0, 0, 0};
};

// Group against a static plane: every primitive vertex within the contact threshold of the
// plane is a candidate; one manifold gets the (at most four) candidates that span the largest
// support polygon, chosen so that a resting body keeps the same points.
class GroupPlaneAlgorithm : public GroupVersusAlgorithm {
public:
    GroupPlaneAlgorithm(const btCollisionAlgorithmConstructionInfo& ci, const btCollisionObjectWrapper* body0,
                        const btCollisionObjectWrapper* body1, bool groupIsBody0);
    ~GroupPlaneAlgorithm() override;
    void processCollision(const btCollisionObjectWrapper* body0, const btCollisionObjectWrapper* body1,
                          const btDispatcherInfo& info, btManifoldResult* result) override;
    // Its own manifold (empty or not), then its leaves' with points.
    void getAllContactManifolds(btManifoldArray& manifolds) override;

    struct Candidate {
        Eigen::Vector3d vertex; // group coordinates, on the primitive (margin not applied)
        double distance;        // signed, margin subtracted: < 0 penetrating
        int primitive;
        int vertexIndex;
    };

private:
    btPersistentManifold* manifold_;
    std::vector<Candidate> candidates_; // kept between steps: no allocation once warm
};

// Group against a concave shape (triangle mesh, height field, GImpact, other custom concave):
// each triangle near the group is tested against the primitives near that triangle; each
// primitive gathers its triangles' contacts in its own manifold.
class GroupConcaveAlgorithm : public GroupVersusAlgorithm {
public:
    using GroupVersusAlgorithm::GroupVersusAlgorithm;
    void processCollision(const btCollisionObjectWrapper* body0, const btCollisionObjectWrapper* body1,
                          const btDispatcherInfo& info, btManifoldResult* result) override;

    struct TriangleHit {
        btVector3 vertices[3]; // concave shape coordinates
        int partId, triangleIndex;
        int primitive;
        int sequence; // order found, for a deterministic stable sort
    };

private:
    std::vector<TriangleHit> hits_; // kept between steps: no allocation once warm
};

// Group against group: primitive pairs from the two contact trees, one child algorithm each.
// The pairs near each other are listed, and each listed pair holds its own leaf entry: two large
// pieces lying against each other (the table's broken top, halves of 1.48 m and 1.28 m along a
// jagged crack) hold tens of thousands of leaf pairs for a few dozen contact points, and a
// leaf cache looked up and sorted by key every step was a fifth of that pair's cost. The
// entries, their manifolds and the order they are made and freed in are those of the cache.
class GroupGroupAlgorithm : public GroupAlgorithmBase {
public:
    GroupGroupAlgorithm(const btCollisionAlgorithmConstructionInfo& ci, const btCollisionObjectWrapper* body0,
                        const btCollisionObjectWrapper* body1);
    ~GroupGroupAlgorithm() override;
    void processCollision(const btCollisionObjectWrapper* body0, const btCollisionObjectWrapper* body1,
                          const btDispatcherInfo& info, btManifoldResult* result) override;
    void getAllContactManifolds(btManifoldArray& manifolds) override;

private:
    bool listStillHolds(const Eigen::Isometry3d& oneToZero, double reach, const GroupShape& g0, const GroupShape& g1) const;
    // A new list of the pairs within `listReach`; each takes its entry from the old list.
    // reachedNow_ says which of them are within `reach` (at most listReach) now.
    void relist(const GroupShape& g0, const GroupShape& g1, const Eigen::Isometry3d& oneToZero, double listReach,
                double reach);
    // A held entry goes to leaving_ (freed, in key order, at the step's end); `entry` is left empty.
    void leave(LeafCache::Entry& entry);
    // The list follows the groups' primitives renumbered since it was made with the bodies in the
    // world (SeenRevision): kept pairs take their new indices, in the same order; the others
    // leave. A pair whose primitives were only removed stands where it stood (a removal moves no
    // primitive in its group's frame), so the list still holds. Primitives renumbered without a
    // map: every pair leaves, and the list is made anew.
    void followRenumbering(const GroupShape& g0, const GroupShape& g1);

    // The bodies' relative pose at each of the last kPoses steps of the group pair, and how far
    // it moved from each to this step's (recordPose), for provenApart.
    static constexpr std::uint32_t kPoses = 16;
    struct PoseAt {
        std::uint64_t step = 0; // 0: none
        Eigen::Matrix3d r;     // body1's turn in body0's frame (RelativePose::bToA, its floats)
        Eigen::Vector3d p, q;  // body1's origin in body0's frame, body0's in body1's (aToB)
    };
    struct MotionSince {
        Eigen::Matrix3d dr;    // r now − r then
        Eigen::Vector3d dp, dq; // p now − p then, q now − q then
        double drNorm;         // Frobenius norm of dr: bounds |dr · x| / |x|
        bool known;
    };
    // Records this step's pose and the motion since each recorded step (the proofs' steps).
    void recordPose(const btTransform& bToA, const btTransform& aToB);
    // Whether the entry's proof shows that running its pair this step would change nothing: a
    // hull pair apart by its face (kept as its hint) with an empty manifold, whose other hull
    // has since moved, relative to that face, less than the proof's budget.
    bool provenApart(const LeafCache::Entry& entry) const;
    std::array<PoseAt, kPoses> poses_{};
    std::array<MotionSince, kPoses> motion_{};
    std::uint64_t step_ = 0;         // steps of the listed path, from 1 (64 bits: never wraps)
    std::uint64_t provenFrom_ = 1;   // proofs made before this step are void (a group changed)
    double originReach_ = 0;         // max(|p|, |q|) now, for the rounding margin
    std::uint64_t provenRevision0_ = 0, provenRevision1_ = 0;

    struct Listed {
        int i, j;
        LeafCache::Entry entry; // this step's or last step's child, or none
    };
    // Primitive pairs (i of body0, j of body1) within listReach_ of each other where the bodies
    // stood at listedAt_ (body0⁻¹ · body1), in the trees' walk order (HullPairContacts::pairListSlack).
    std::vector<Listed> listed_;
    // Whether listed_[k] was within the contact reach when relist made the list (read in that
    // step only; the box test's answer, NearBox::withinBoth).
    std::vector<std::uint8_t> reachedNow_;
    std::vector<LeafCache::Entry> leaving_; // entries the step did not reach: freed at its end
    // Scratch of relist: the old list, and the keys of its entries with their places, by key.
    std::vector<Listed> oldList_;
    std::vector<std::pair<std::uint64_t, std::uint32_t>> oldKeys_;
    Eigen::Isometry3d listedAt_ = Eigen::Isometry3d::Identity();
    double listReach_ = -1.0; // < 0: no list
    std::uint64_t listedRevision0_ = 0, listedRevision1_ = 0;
    bool seen_ = false; // the groups' revisions were seen (from the first step on)
};

// How many group-group leaf pair runs this thread skipped as proven apart (skipProvenApart):
// for tests, which check that the skip happens. It counts the calling thread's narrowphase
// only (a thread-local count): skips on the worker threads of a multi-threaded dispatcher
// (btCollisionDispatcherMt) are not in it.
std::uint64_t provenApartSkips();

// Picks the algorithm from the pair's shapes at creation. Shapes of type kGroupShapeType
// that are not a GroupShape (Bullet's btSdfCollisionShape has the same type id) get the
// collision configuration's own algorithm, as if nothing had been registered.
class GroupAlgorithmCreateFunc : public btCollisionAlgorithmCreateFunc {
public:
    explicit GroupAlgorithmCreateFunc(ebtDispatcherQueryType queryType) : queryType_(queryType) {}
    btCollisionAlgorithm* CreateCollisionAlgorithm(btCollisionAlgorithmConstructionInfo& ci,
                                                   const btCollisionObjectWrapper* body0,
                                                   const btCollisionObjectWrapper* body1) override;

private:
    ebtDispatcherQueryType queryType_;
};

} // namespace shatter
