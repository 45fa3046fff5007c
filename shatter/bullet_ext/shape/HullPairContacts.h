#pragma once
// Keeping a hull pair's contact manifold between face clips.
//
// For two hulls with polyhedral features, Bullet clips faces every step (after its
// separating-axis test or GJK finds the normal) and refills the pair's manifold with up to four
// points spanning the contact face. In a heap of fragments that is much of the narrowphase,
// although a resting pair's points hardly move: Bullet's manifold refresh already carries them
// with the bodies, updates their depths and drops the ones that drift or separate. So a pair
// whose manifold still holds `minPoints` points and whose two hulls have moved relative to each
// other by less than `reclipAfter` times the manifold's breaking threshold since its last clip
// is only refreshed: a new contact region cannot open without at least that much motion. A pair
// that lost points (it turned, slid or landed on a new face) or moved further is clipped again.
// (Adding one GJK point per step instead, as Bullet does for hulls without features, replaces a
// clipped corner by an arbitrary point of the face: a stack of cubes then never comes to rest.)
#include <BulletCollision/BroadphaseCollision/btCollisionAlgorithm.h>
#include <BulletCollision/CollisionDispatch/btCollisionObjectWrapper.h>
#include <BulletCollision/CollisionDispatch/btManifoldResult.h>
#include <BulletCollision/NarrowPhaseCollision/btPersistentManifold.h>

namespace shatter {

struct HullPairContacts {
    // Motion (fraction of the manifold's contact breaking threshold) after which a pair is
    // clipped again; 0 clips every step (Bullet's own behaviour).
    double reclipAfter = 0.25;
    // A manifold with fewer points is clipped again at once. 1: an edge or corner contact (1-2
    // points, a third of the vase's touching pairs) is kept too; the stack and energy tests
    // (GroupLeafReclip, FractureSystem.PiecesMadeTouchingAtRestGainNoEnergy) pass with it.
    int minPoints = 1;
    // Group-group pairs (GroupGroupAlgorithm) list the primitive pairs within this distance (m)
    // beyond their contact reach and reuse the list, with the exact box test still applied to
    // each, until the two bodies have moved that far relative to each other: the leaf pairs
    // in the order of walking both trees every step, which 0 does. (The box test's slack is
    // along its 15 axes, which turn with the bodies: a pair only that test's grown corners
    // reach, up to √3 × the slack apart, may be missed by a kept list and its cache entry
    // freed one step early; every pair close enough to make a point is listed. Same scene,
    // same bits either way; the lattice and fracture scenes gave the same results as 0.)
    double pairListSlack = 0.005;
    // A list is made by walking both groups' trees (their boxes grown by the contact slacks)
    // only as deep as the list's reach needs (relistDepth, NearBox.h). False walks them whole:
    // the same list, in the same order, more slowly (the reference the pair-list tests compare
    // the pruned walk with).
    bool pruneRelist = true;
    // A rigid group's hull primitives against a btBoxShape (GroupConvexAlgorithm): true gives
    // them the hull pairs' contacts, the box taken as a polyhedron, the separating-axis test
    // and face clipping (PolyhedronContacts.h): exact face normals, points only where
    // primitive and box overlap, so a group rests on the box's surface (GJK: a margin above
    // it), and a full face of points at once. False (the default) keeps Bullet's GJK and EPA,
    // one point a step: true changes what rests on boxes, and so the chaotic lattice scenes
    // (the bench's table, whose top lies on box legs: 328 fragments instead of 258).
    bool boxLeavesClipped = false;
    // A group with one contact per primitive (GroupShape::contactPerPrimitive: a soft body)
    // against a btBoxShape: true (the default) gives each touching primitive GJK's one point a
    // step, a margin off the hull, but exact and from a separating-axis test in the box's frame
    // (hullBoxContact); false keeps Bullet's GJK and EPA, which overstates the gap of a face
    // lying nearly flat on the box by up to 3 mm (HullBoxContact test), so what presses on a
    // soft body sinks further. The exact test is also cheaper: a 4,900-quad soft sheet lying
    // on a table spends 1.27 G instructions in collision detection over 60 frames instead of
    // 3.06 G; its frames -10% median, -17-22% worst (shatter-bench-oriented --scenes sheet,
    // against --gjk-soft-box-contacts).
    bool softBoxContacts = true;
    // The order the world's solver and the Plugin's contact snapshot take the contact manifolds
    // in: Bullet's (their places in the dispatcher, which every manifold made or freed moves)
    // or Shatter's own (OrderedContacts.h: by bodies, then by leaf pair), which is what lets
    // keepEmptyLeafManifolds be off without changing any result. The Plugin reads it when it
    // is made: for the own order it puts a solver of its own in front of the world's, which
    // needs a btSequentialImpulseConstraintSolver (not a multibody one) that the application
    // passed to the world (one the world made itself it frees itself), in a single-threaded
    // world (btDiscreteDynamicsWorldMt solves its islands with solvers of its own). An
    // application that replaces the world's solver afterwards puts the world back in Bullet's
    // order (Plugin::takeWarnings() says so).
    //  - Bullets (the default): Bullet's order, every empty manifold kept;
    //  - Own: the own order, an InputError where the world's solver does not allow it;
    //  - OwnWherePossible: the own order where the world's solver allows it, else Bullet's for
    //    that world, with its empty manifolds kept (Plugin::contactsOrdered() says which, and a
    //    warning from Plugin::takeWarnings() says why).
    // The own order changes every result once (a new solver order), and not only in detail:
    // the bench's table (shatter-bench-lattice --scene table, seeds 1-4) breaks into 139
    // fragments on average instead of 240 (its two halves come to rest leaning on each other
    // instead of crashing together), which is beyond issue 14's "fragment counts within 10%";
    // the wall's spread over seeds 1-8 is the same (541 ± 198 against 501 ± 204). Where it
    // applies, it removes the table's hitch of 34,000-40,000 empty leaf manifolds (seed 1:
    // worst frame 115 -> 49 ms, p99 108 -> 24 ms on a quiet host).
    enum class ContactOrder { Bullets, Own, OwnWherePossible };
    ContactOrder contactOrder = ContactOrder::Bullets;
    // False (the default) gives a hull leaf pair a manifold only while it holds points, in a
    // world whose contacts are taken in the own order (above): the same points, solved in the
    // same order (the table's runs are bit for bit those of keeping them), for the cost of the
    // manifolds that hold some. The table's two broken halves lying against each other held
    // about 38,000 empty leaf manifolds for a few dozen points, and Bullet's island manager
    // and solver setup walk them all every step. True keeps a leaf pair's manifold, empty or
    // not, while the pair is listed, as Bullet's compound keeps its children's. In Bullet's
    // order an empty manifold still decides in which order the others are solved, so there
    // they are always kept (this setting then changes nothing).
    bool keepEmptyLeafManifolds = false;
    // Group-group hull pairs (GroupGroupAlgorithm) found apart by a face plane, with an empty
    // manifold, are not tested again while a bound on the bodies' relative motion since then
    // proves that face still separates them (ApartProof, GroupCollisionAlgorithms.h): the test
    // would find the same face and add nothing. The same flag lets new pairs apart by a face
    // plane by more than their rounding skip the full separating-axis test (newPairApart in
    // GroupCollisionAlgorithms.cpp; it starts them with that face as their hint). Same
    // results either way, bit for bit, for bodies whose bases are orthonormal to float
    // rounding, as Bullet's integration keeps them (kRoundingPerMetre's comment there).
    bool skipProvenApart = true;
};

// The contact settings of the world's group shapes, read by their collision algorithms at every
// step. They apply to the primitive pairs of group shapes with each other or with an
// application's hull. A lattice fragment's pairs (its FragmentHull with anything, also as a
// group's leaf) keep FragmentPairAlgorithm's own test and a clip every step: with only refreshed
// points there, a broken wall's loose pieces froze where one could slide off
// (LatticeFreezing.ABrokenWallsLoosePiecesFreezeWhereTheyRest: a piece fell 2.3 cm once thawed).
HullPairContacts& hullPairContacts();

// Where a pair's two bodies stood relative to each other at its last clip.
struct LastClip {
    btTransform relative = btTransform::getIdentity(); // body0⁻¹ · body1, in the result's order
    bool valid = false;
};

// When the pair may keep its manifold this step (see above): refreshes it and returns true.
// Otherwise returns false, and the caller clips and then calls `clipped`. The result must point
// at the manifold and wrap the two hulls.
bool keptWithoutClip(btPersistentManifold& manifold, btManifoldResult& result, const LastClip& last,
                     const HullPairContacts& settings);
void clipped(LastClip& last, const btManifoldResult& result);
// The same, with the result's body0⁻¹ · body1 given: the leaf pairs of two groups share their
// bodies' transforms, and so this product (made once per group pair, not once per clip).
void clipped(LastClip& last, const btTransform& relative);

// The one manifold of a hull pair's algorithm, or null (none yet, or several). Through a
// reused array: a btManifoldArray on the stack allocates on every pair of every step.
btPersistentManifold* soleManifold(btCollisionAlgorithm& algorithm);

} // namespace shatter
