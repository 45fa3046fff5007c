#pragma once
// Removing primitives from a body's group shape with the body left in the world, the other way
// to OutOfWorld.h (LatticeSettings::keepPairsOnShrink). Bullet's pairs of the body then keep
// their collision algorithms, and the group algorithms keep their leaf pairs with their
// manifolds: at their next step they follow the shape's renumbering (GroupShape::indexMapFrom).
// The manifolds' points are made to follow here, at once, so that nothing (the solver, a
// contact snapshot of a pair asleep) reads a point on a primitive that is gone or a point
// recorded in the body's old frame.
#include <BulletCollision/BroadphaseCollision/btDispatcher.h>
#include <BulletCollision/CollisionDispatch/btCollisionObject.h>
#include <LinearMath/btTransform.h>

#include <span>

namespace shatter {

// After primitives of `body`'s group shape were removed in place (`to`: each old primitive's
// new index, −1 removed) and its frame moved from `before` to where the body is now (the centre
// of mass moved: VisualBody::reframe; the group itself stays where it was in the world): every
// point of the body's manifolds on a removed primitive goes, the others name their primitive's
// new index, and their local points on the body are re-based to the new frame (their world
// positions do not change). They keep their impulses, which the solver starts from (warm
// starting), as on any kept point. (Dropping them, so that the solver met them as the new points
// made out of the world, broke the table benchmark into a third fewer fragments over seeds 1-8.)
void followRemoval(btDispatcher& dispatcher, const btCollisionObject& body, std::span<const int> to,
                   const btTransform& before);

} // namespace shatter
