#pragma once
// Bullet collision shape for a group of convex polyhedra (source 000 §3.1-3.2): one rigid
// body, from a handful to tens of thousands of primitives, with its own bounding-volume tree.
#include <shatter/plugin/geometry/AabbTree.h>
#include <shatter/plugin/geometry/ConvexPolyhedron.h>

#include <BulletCollision/BroadphaseCollision/btCollisionAlgorithm.h>
#include <BulletCollision/CollisionDispatch/btCollisionDispatcher.h>
#include <BulletCollision/CollisionShapes/btConcaveShape.h>
#include <BulletCollision/CollisionShapes/btConvexHullShape.h>

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <utility>
#include <vector>

namespace shatter {

// The shape type id Shatter uses for the group shape. It is Bullet's CUSTOM_CONCAVE_SHAPE_TYPE,
// so Bullet's ray and convex-sweep tests reach the primitives through processAllTriangles.
// Bullet 3.24 gives btSdfCollisionShape the same id (SDF_SHAPE_PROXYTYPE), and its own
// convex-concave algorithm reads such shapes as SDFs: a world with group shapes needs
// registerGroupShapeAlgorithms() (shatter::Plugin calls it).
constexpr int kGroupShapeType = CUSTOM_CONCAVE_SHAPE_TYPE;

class GroupShape : public btConcaveShape {
public:
    // Primitives in the body frame (the rigid body's centre-of-mass principal frame).
    // `margin` (m) is Bullet's collision margin around each primitive. Throws
    // shatter::InputError for an empty primitive list or a negative or non-finite margin.
    GroupShape(std::vector<geometry::ConvexPolyhedron> primitives, double margin);
    // A soft body's part as a shape of its own, its hulls taken from `from` (the soft shape
    // of the body it was torn from) instead of built again: primitive k is from's primitive
    // indices[k], moved over with its child hull and rest edges; rest[k] is its rest layout
    // (what setPrimitivePoses is given). The result is, bit for bit, the shape built from
    // `rest` at the identity pose and then moved where from's primitives are by
    // setPrimitivePoses (a torn part's new body): the hulls' inner spheres are those of rest,
    // and the trees are built over the rest boxes, then refitted. Only the primitives' global
    // ids stay from's (nothing in the shape reads them), and its box (getAabb) is the rest
    // primitives' until fitBox(): the box a new shape of `rest` has before it is posed, so
    // that the part's body enters the world where a new body of it would (Bullet's broadphase
    // pairs a body as it enters, and the pairs' order orders the contacts), then moves.
    // `from` keeps empty slots at `indices` and must drop them (removePrimitives) before
    // anything else reads it. Throws shatter::InputError for no index, indices not strictly
    // increasing, an index out of range or taken already, or a rest list of another length.
    GroupShape(GroupShape& from, const std::vector<int>& indices, const std::vector<geometry::ConvexPolyhedron>& rest);
    ~GroupShape() override;

    int primitiveCount() const { return int(primitives_.size()); }
    const std::vector<geometry::ConvexPolyhedron>& primitives() const { return primitives_; }
    const geometry::AabbTree& tree() const { return tree_; }
    // The same tree over primitive boxes grown by contactSlack(), for group-group pairs:
    // two contact trees overlap wherever primitives of the two groups may touch, so resting
    // pairs (micrometres apart, either way) are not lost to an exact box test. The margin
    // is not added: hull-hull pairs take Bullet's separating-axis path, which makes contact
    // points only where the primitives themselves overlap.
    // Refitted when first asked for after the primitives moved: only group-group pairs use it,
    // and a soft body that touches no other group (a sheet on a table) never does.
    const geometry::AabbTree& contactTree() const {
        if (contactTreeStale_) refitContactTree();
        return contactTree_;
    }
    // Growth of the contact tree's boxes (m): half of Bullet's contact breaking threshold
    // (gContactBreakingThreshold) at construction, so a pair of groups finds primitives up
    // to that threshold apart.
    double contactSlack() const { return contactSlack_; }
    // Bullet view of primitive i (a btConvexHullShape with polyhedral features), used by
    // the collision algorithms. After a soft step (setPrimitivePoses) the hull is moved here,
    // on first use: only primitives near another body are ever asked for (a sheet draped on
    // a table: a quarter of them), and moving every hull each step was a quarter of the refit.
    // A hull is built on first use too: a fracture makes thousands of primitives at once
    // (the fragments' and the rest's), of which only those that touch something are asked for.
    const btConvexHullShape& child(int i) const {
        if (!children_[size_t(i)]) buildHull(i);
        else if (!staleHulls_.empty() && staleHulls_[size_t(i)]) moveHull(i);
        return *children_[size_t(i)];
    }

    // Changes whenever primitives move, are replaced or removed (the three calls below):
    // collision algorithms that keep lists of primitive pairs between steps rebuild them.
    std::uint64_t revision() const { return revision_; }
    // Whether primitives were removed or replaced since revision `since`: an index of then may
    // name another primitive (or none) now. (A soft step moves primitives but keeps their indices.)
    bool renumberedSince(std::uint64_t since) const { return renumberedAt_ > since; }
    // Where each primitive of revision `since` is now (−1: removed), when every edit since then
    // removed primitives and added none (removePrimitives), up to kRemovalChain of them; empty
    // when `since` is the current revision or the edits since were others. Collision algorithms
    // kept across such an edit, with the body left in the world (LatticeSettings::keepPairsOnShrink),
    // follow their leaf pairs with it.
    std::vector<int> indexMapFrom(std::uint64_t since) const;
    static constexpr int kRemovalChain = 4;

    // Against a plane, a rigid group gets the 4 contact points that best support it; a group
    // whose primitives move on their own (a soft body) needs every touching primitive's
    // deepest point instead. Off by default.
    void setContactPerPrimitive(bool on) { contactPerPrimitive_ = on; }
    bool contactPerPrimitive() const { return contactPerPrimitive_; }

    // Replaces some primitives (same vertex and face layout as before, e.g. moved rigidly by
    // a dent) and refits the trees: cost O(replaced + primitive count), no rebuild. Only
    // while no collision pair refers to the shape (its body out of the world): cached
    // algorithms point at the children being replaced.
    void replacePrimitives(const std::vector<int>& indices, const std::vector<geometry::ConvexPolyhedron>& replacements);
    // Removes the primitives at `indices` (any order) and appends `added` after the rest:
    // the rest keep their child hulls and their relative order (primitive i is then the i-th
    // survivor), so a caller's map from primitive index to its own items stays a plain
    // compaction; the added ones get their hulls on first use. The trees keep the rest's branches
    // (AabbTree::removeAndAppend): O(n + m log m) for m added. Only while no collision pair
    // refers to the shape (its body out of the world): cached algorithms are keyed by
    // primitive index. Or, with none added, in the world through SystemContext::removeInWorld:
    // the group algorithms then follow indexMapFrom. Throws shatter::InputError for an index
    // out of range or when none would be left.
    void removePrimitives(const std::vector<int>& indices, std::vector<geometry::ConvexPolyhedron> added = {});
    // Rigid shape: the same edit with the places of geometry::fillHoles(primitiveCount(),
    // removed, added.size()) instead of closing up in order: the added primitives take the
    // removed ones' places and the last survivors fill the holes left, each with its child
    // hull. O(removed + added) primitives moved, and the trees edited from the removed
    // leaves up (AabbTree::fillHoles), where removePrimitives moves every survivor after the
    // first hole and passes over both trees: a fracture's rest loses a few hundred of tens of
    // thousands. `removed` ascending, distinct; the rest as removePrimitives
    // (out of the world, errors), and the soft step's rest edges are dropped.
    void fillPrimitives(const std::vector<int>& removed, std::vector<geometry::ConvexPolyhedron> added);
    // The same edit with `added` pieces, each moved rigidly by `toShape` (bit for bit its
    // moved(toShape)), read from `edited`: primitives edited with the same places, the added
    // piece j at slots.addedAt[j] (a mesh after fracture::applyRemainderEdit). A piece that
    // takes a removed primitive's place is written into that primitive's storage, where a
    // moved copy allocated three blocks and the removed one freed three (~1,000 instructions
    // a piece, ~380 pieces in a 64-cell break of the 16k shell).
    void fillPrimitives(const std::vector<int>& removed, const std::vector<geometry::ConvexPolyhedron>& edited,
                        int added, const Eigen::Isometry3d& toShape);
    // A soft body's step: primitive i becomes rest[i] moved rigidly by poses[i] (rest[i] has
    // the layout primitive i was built from). Vertices, face planes and Bullet hulls are
    // moved in place, not rebuilt; both trees are refitted bottom-up and the shape's box
    // follows (the Bullet hulls when first asked for: child()). O(primitives), nothing
    // allocated once warm, and unlike the two above it may
    // run while the body is in the world: cached algorithms keep their children. The caller
    // tells the broadphase the new box (btCollisionWorld::updateSingleAabb) and clears the
    // body's manifolds, whose points were recorded on the primitives where they were. The
    // hulls' inner boxes (Bullet's separating-axis shortcut) shrink to their inner spheres,
    // which do not depend on the turn. Mass properties of the whole shape are not updated.
    void setPrimitivePoses(const std::vector<geometry::ConvexPolyhedron>& rest, std::span<const Eigen::Isometry3d> poses);
    // The shape's box becomes the one around its primitives where they are (after the taking
    // constructor; setPrimitivePoses ends with it).
    void fitBox();

    // btCollisionShape
    void getAabb(const btTransform& t, btVector3& aabbMin, btVector3& aabbMax) const override;
    // Only (1,1,1) is supported: primitives are exact polyhedra in the body frame, and a
    // scaled body is a new set of primitives. Any other value is ignored and reported once
    // per shape on stderr.
    void setLocalScaling(const btVector3& scaling) override;
    const btVector3& getLocalScaling() const override;
    void calculateLocalInertia(btScalar mass, btVector3& inertia) const override;
    const char* getName() const override { return "ShatterGroupShape"; }
    // Sets the margin of every child hull too.
    void setMargin(btScalar margin) override;
    btScalar getMargin() const override { return margin_; }
    // btConcaveShape: the triangles of every primitive whose box, grown by the margin,
    // overlaps [aabbMin, aabbMax] (shape coordinates); Bullet's ray and sweep tests use this.
    // Faces are fanned from their first vertex, counter-clockwise seen from outside;
    // partId = primitive index, triangleIndex = running index within the primitive.
    void processAllTriangles(btTriangleCallback* callback, const btVector3& aabbMin, const btVector3& aabbMax) const override;

private:
    // tree_ over the primitives' boxes as they are, contactTree_ over them grown by the contact slack.
    void buildTrees();
    // The trees a shape built over `boxes` has, the contact tree not yet refitted to them grown.
    void buildTrees(const std::vector<geometry::Aabb>& boxes);
    // Each rest primitive's unique edge directions, appended (setPrimitivePoses' first call).
    void addRestEdges(const std::vector<geometry::ConvexPolyhedron>& rest);
    void updateBounds();
    // fillPrimitives in two halves, around placing the added primitives at slots.addedAt:
    // checks, then the survivors moved into the holes (the places returned); then the trees
    // and the shape's box.
    geometry::HoleFilling startFilling(const std::vector<int>& removed, int added);
    void finishFilling(const std::vector<int>& removed, const geometry::HoleFilling& slots);
    // removePrimitives without added ones: `to` joins the chain indexMapFrom reads.
    void noteRemoval(const std::vector<int>& to);
    // Refits tree_ to the primitives' boxes; the contact tree waits for contactTree().
    void refitTrees();
    void refitContactTree() const;
    // removePrimitives: the survivors' rest edges follow them (`to`: new index, −1 removed);
    // with primitives added, all are dropped.
    void keepRestEdges(const std::vector<int>& to, bool nothingAdded);
    // Builds child hull i over its primitive as it is now: the hull the shape would have built
    // when the primitive came (the primitive has not changed since: a step, a replacement and a
    // new margin build every waiting hull first).
    void buildHull(int i) const;
    void buildAllHulls() const;
    // Moves child hull i onto its primitive, as setPrimitivePoses left it.
    void moveHull(int i) const;
    // Moves every hull still waiting for its step (before the children are moved, taken,
    // replaced or given a new margin), so each is as an eager step would have left it.
    void moveStaleHulls();

    std::vector<geometry::ConvexPolyhedron> primitives_;
    // Null until first asked for (child()); a taken slot's primitive has no vertices left.
    mutable std::vector<std::unique_ptr<btConvexHullShape>> children_;
    geometry::AabbTree tree_;
    // contactTree(): refitted on first use after refitTrees (Bullet's algorithms see a const
    // shape); the refit is the one an eager step would have made.
    mutable geometry::AabbTree contactTree_;
    mutable bool contactTreeStale_ = false;
    double contactSlack_ = 0.0;
    btScalar margin_;
    btVector3 localAabbMin_, localAabbMax_; // without the margin
    // Principal moments per kilogram, computed when Bullet asks (calculateLocalInertia): Shatter
    // gives its bodies their exact inertia itself, and a pass over every primitive's mass
    // properties at each edit cost a fracture event a fifth of its edit of the rest.
    mutable std::optional<Eigen::Vector3d> unitInertia_;
    btVector3 unitScaling_{1, 1, 1};
    bool scalingWarned_ = false;
    bool contactPerPrimitive_ = false;
    std::uint64_t revision_ = 0;
    std::uint64_t renumberedAt_ = 0; // the revision of the last removal or replacement
    // The last removals (indexMapFrom), each with the revision it made, oldest first; cleared by
    // any other edit.
    struct Removal {
        std::uint64_t revision;
        std::vector<int> to;
    };
    std::vector<Removal> removals_;
    // setPrimitivePoses: each rest primitive's unique edge directions (Bullet's edge-edge
    // axes), from the first call on, and the box buffers of the refit.
    std::vector<btVector3> restEdges_;
    std::vector<int> restEdgeOffsets_;
    std::vector<geometry::Aabb> boxes_;
    mutable std::vector<geometry::Aabb> grownBoxes_;
    // setPrimitivePoses: each primitive's turn from rest (Bullet's precision, the one its hull's
    // edges are turned with), and which hulls child() has not yet moved (empty: none waits).
    // Bullet asks for children through a const shape; the move changes nothing it could have
    // read before.
    std::vector<btMatrix3x3> hullTurns_;
    mutable std::vector<char> staleHulls_;
};

// The polyhedral features a group shape gives primitive `p`'s Bullet hull (child()): its own
// vertices, faces and planes, Bullet's unique edge directions and inner box, appended to the
// empty `features`. For a hull standing for the primitive without a group built around it.
void primitiveFeatures(const geometry::ConvexPolyhedron& p, btConvexPolyhedron& features);

// Registers the group shape's contact and closest-point algorithms with a dispatcher, in both
// argument orders, against every Bullet shape type except btCompoundShape (Bullet's compound
// algorithm already hands each child to the dispatcher, which brings child-vs-group back to
// us) and soft bodies. See GroupCollisionAlgorithms.h.
void registerGroupShapeAlgorithms(btCollisionDispatcher& dispatcher);
// Puts back the algorithms the dispatcher's collision configuration gives for those pairs
// (not any the application registered there before).
void unregisterGroupShapeAlgorithms(btCollisionDispatcher& dispatcher);

} // namespace shatter
