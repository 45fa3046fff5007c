#pragma once
// Bullet collision shape for a group of convex polyhedra (source 000 §3.1-3.2): one rigid
// body, from a handful to tens of thousands of primitives, with its own bounding-volume tree.
#include "plugin/geometry/AabbTree.h"
#include "plugin/geometry/ConvexPolyhedron.h"

#include <BulletCollision/BroadphaseCollision/btCollisionAlgorithm.h>
#include <BulletCollision/CollisionDispatch/btCollisionDispatcher.h>
#include <BulletCollision/CollisionShapes/btConcaveShape.h>
#include <BulletCollision/CollisionShapes/btConvexHullShape.h>

#include <memory>
#include <vector>

namespace shatter {

// The shape type id Shatter uses for the group shape. It is Bullet's CUSTOM_CONCAVE_SHAPE_TYPE,
// so Bullet's ray and convex-sweep tests reach the primitives through processAllTriangles.
constexpr int kGroupShapeType = CUSTOM_CONCAVE_SHAPE_TYPE;

class GroupShape : public btConcaveShape {
public:
    // Primitives in the body frame (the rigid body's centre-of-mass principal frame).
    // `margin` (m) is Bullet's collision margin around each primitive.
    GroupShape(std::vector<geometry::ConvexPolyhedron> primitives, double margin);
    ~GroupShape() override;

    int primitiveCount() const { return int(primitives_.size()); }
    const std::vector<geometry::ConvexPolyhedron>& primitives() const { return primitives_; }
    const geometry::AabbTree& tree() const { return tree_; }
    // Bullet view of primitive i (a btConvexHullShape with polyhedral features), used by
    // the collision algorithms.
    const btConvexHullShape& child(int i) const { return *children_[i]; }

    // btCollisionShape
    void getAabb(const btTransform& t, btVector3& aabbMin, btVector3& aabbMax) const override;
    void setLocalScaling(const btVector3& scaling) override; // only (1,1,1) is supported
    const btVector3& getLocalScaling() const override;
    void calculateLocalInertia(btScalar mass, btVector3& inertia) const override;
    const char* getName() const override { return "ShatterGroupShape"; }
    void setMargin(btScalar margin) override;
    btScalar getMargin() const override { return margin_; }
    // btConcaveShape: the triangles of every primitive whose box overlaps [aabbMin, aabbMax]
    // (shape coordinates); Bullet's ray and sweep tests use this.
    void processAllTriangles(btTriangleCallback* callback, const btVector3& aabbMin, const btVector3& aabbMax) const override;

private:
    std::vector<geometry::ConvexPolyhedron> primitives_;
    std::vector<std::unique_ptr<btConvexHullShape>> children_;
    geometry::AabbTree tree_;
    btScalar margin_;
    btVector3 localAabbMin_, localAabbMax_;
    Eigen::Vector3d unitInertia_; // principal moments per kilogram
};

// Registers the group shape's contact and closest-point algorithms with a dispatcher,
// against every Bullet shape type, in both argument orders.
void registerGroupShapeAlgorithms(btCollisionDispatcher& dispatcher);
// Puts back the algorithms the dispatcher's collision configuration gives for those pairs.
void unregisterGroupShapeAlgorithms(btCollisionDispatcher& dispatcher);

} // namespace shatter
