#pragma once
// A body's shape in its principal frame: a compound whose one child is the body's group shape,
// placed where the body frame sees it (VisualBody::reframe), that remembers its angular motion
// disc.
#include <BulletCollision/CollisionShapes/btCompoundShape.h>

namespace shatter {

// Bullet asks a body's shape for its contact breaking threshold (the angular motion disc times
// gContactBreakingThreshold) twice at every new manifold, and the group algorithms once per
// group pair and step; btCompoundShape works the disc out from its bounding box each time (two
// getAabb calls through getBoundingSphere): 3% of the table's instructions. The disc depends
// only on the compound's local box, its margin and whether it has children. The box changes
// only in recalculateLocalAabb (virtual: also what updateChildTransform, removeChildShape and
// setLocalScaling call) and addChildShape; the children in addChildShape and
// removeChildShapeByIndex (both count the shape's update revision); the margin only in
// setMargin (virtual). So the disc is remembered at the
// two virtual ones, with the revision, and given while the revision is the same: exactly the
// value Bullet computes. It is remembered only where the shape is changed, never in the const
// query, which several threads may run at once.
class FramedShape : public btCompoundShape {
public:
    FramedShape() : btCompoundShape(/*enableDynamicAabbTree=*/false, 1) {}

    btScalar getAngularMotionDisc() const override {
        return rememberedAt_ == m_updateRevision ? disc_ : btCompoundShape::getAngularMotionDisc();
    }
    void recalculateLocalAabb() override;
    void setMargin(btScalar margin) override;

private:
    void remember();

    int rememberedAt_ = 0; // the update revision the disc is for; Bullet's revisions start at 1
    btScalar disc_ = 0;
};

} // namespace shatter
