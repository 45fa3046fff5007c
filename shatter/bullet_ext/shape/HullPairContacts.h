#pragma once
// Keeping a hull pair's contact manifold up between full face clips.
//
// For two hulls with polyhedral features, Bullet clips faces every step (after its
// separating-axis test or GJK finds the normal) and refills the pair's manifold with up to four
// points spanning the contact face. In a heap of fragments that is most of the narrowphase
// (the vase's heap: a third of its frames in btConvexPolyhedron::project alone), although a
// resting pair's points hardly move: Bullet's manifold refresh already carries them with the
// bodies and drops the ones that drift or separate. So a pair whose manifold still holds
// `clipBelowPoints` points after the refresh gets only its deepest point from GJK (and EPA) on
// the hulls' cores, measured as the clip measures, hull surface to hull surface with no margin;
// the manifold merges it with the nearest old point. A pair that lost points (it turned, slid
// or landed on a new face) is clipped again the same step.
#include <BulletCollision/BroadphaseCollision/btCollisionAlgorithm.h>
#include <BulletCollision/CollisionDispatch/btCollisionObjectWrapper.h>
#include <BulletCollision/CollisionDispatch/btManifoldResult.h>
#include <BulletCollision/NarrowPhaseCollision/btPersistentManifold.h>

namespace shatter {

struct HullPairContacts {
    // A pair whose refreshed manifold holds at least this many points keeps it with one GJK
    // point per step instead of a new clip; 0 clips every step (Bullet's own behaviour). At 3
    // a resting pair keeps a support triangle or better.
    int clipBelowPoints = 3;
};

// The contact settings of the world's hull pairs (fragment hulls and the primitives of group
// shapes), read by the collision algorithms at every step.
HullPairContacts& hullPairContacts();

// When `manifold` (the pair's, filled by the clip in earlier steps) still holds at least
// `settings.clipBelowPoints` points after Bullet's refresh, adds the pair's deepest core point
// (if within the manifold's breaking threshold) and returns true; returns false, having only
// refreshed, when the pair must be clipped this step. The result must point at the manifold
// and wrap the two hulls (both convex).
bool keptByGjk(btPersistentManifold* manifold, btManifoldResult* result, const HullPairContacts& settings);

// The one manifold of a hull pair's algorithm, or null (none yet, or several). Through a
// reused array: a btManifoldArray on the stack allocates on every pair of every step.
btPersistentManifold* soleManifold(btCollisionAlgorithm& algorithm);

} // namespace shatter
