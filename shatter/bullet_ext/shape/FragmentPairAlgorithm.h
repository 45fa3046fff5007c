#pragma once
// Two convex hulls in contact with each other, one of them a fragment's (FragmentHull): a quick
// separating-plane test first, and contacts only for the pairs it cannot separate: Bullet's own
// convex-convex algorithm, or, with the separating-axis test on (a group's leaf against a
// fragment, as debris against a broken wall), the same test and clip done in one hull's frame
// (PolyhedronContacts.h). In a heap of fragments most box pairs do not touch (the wall benchmark after
// its break: 9,000 pairs, 1,500 contact points), and Bullet runs GJK on every one of them each
// step; a face plane of either hull with all of the other hull's vertices in front of it, by
// more than the margins and the contact breaking threshold, proves the pair can make no
// contact at a fraction of that cost.
#include <BulletCollision/BroadphaseCollision/btCollisionAlgorithm.h>
#include <BulletCollision/CollisionDispatch/btActivatingCollisionAlgorithm.h>
#include <BulletCollision/CollisionDispatch/btCollisionCreateFunc.h>
#include <BulletCollision/CollisionDispatch/btCollisionDispatcher.h>
#include <BulletCollision/CollisionShapes/btConvexPolyhedron.h>

namespace shatter {

class FragmentPairAlgorithm : public btActivatingCollisionAlgorithm {
public:
    FragmentPairAlgorithm(const btCollisionAlgorithmConstructionInfo& ci, const btCollisionObjectWrapper* body0,
                          const btCollisionObjectWrapper* body1);
    ~FragmentPairAlgorithm() override;

    void processCollision(const btCollisionObjectWrapper* body0, const btCollisionObjectWrapper* body1,
                          const btDispatcherInfo& info, btManifoldResult* result) override;
    btScalar calculateTimeOfImpact(btCollisionObject* body0, btCollisionObject* body1, const btDispatcherInfo& info,
                                   btManifoldResult* result) override;
    void getAllContactManifolds(btManifoldArray& manifolds) override;

private:
    // The pair's manifold: Bullet's algorithm's, or the one polyhedronContacts fills.
    btPersistentManifold* manifold();
    // The larger of the two shapes' contact breaking thresholds, kept while the shapes and
    // Bullet's factor stay the same: a shape's threshold comes from its bounding sphere (its
    // box, through a virtual call), which cost a leaf pair as much as its face-plane test.
    // A soft body's leaf hull moves in place, so its threshold drifts (by 2% of how far its
    // centre moves from the body's origin); the pair keeps the value from when it met, as
    // Bullet's manifold keeps the threshold it was made with.
    btScalar threshold(const btCollisionShape* a, const btCollisionShape* b);

    btPersistentManifold* givenManifold_; // the one a caller (a group's leaf) asked the pair to use, or null
    btCollisionAlgorithm* inner_ = nullptr; // Bullet's, made on the first pair it cannot separate
    // With the separating-axis test on (a group's leaf pairs) and both hulls polyhedral, the
    // contacts come from polyhedronContacts (PolyhedronContacts.h: Bullet's test and clip at
    // a fraction of the cost) into this manifold, the given one or one of our own.
    btPersistentManifold* satManifold_ = nullptr;
    bool ownsSatManifold_ = false;
    int separatingFace_ = -1;               // the face that separated the pair last step (separatingFace)
    // The axis that last separated the pair in the separating-axis test (polyhedronContacts),
    // tried first there: a pair the face planes cannot keep apart by the margins and the
    // threshold (debris touching, or a hair from, the wall tets it broke from) is mostly kept
    // apart by the same face or edge pair from step to step.
    int separatingAxis_ = -1;
    const btCollisionShape* thresholdShapes_[2] = {nullptr, nullptr}; // threshold(): what threshold_ is of
    btScalar thresholdFactor_ = 0;
    btScalar threshold_ = 0;
};

// The polyhedral features of a wrapped hull (a btPolyhedralConvexShape), or null if it has none.
const btConvexPolyhedron* polyhedronOf(const btCollisionObjectWrapper* w);
// Whether a face plane of either hull (with polyhedral features) has every vertex of the other
// in front of it by more than `gap` (m; the margins and the contact threshold). False when a
// hull has no polyhedral features (nothing is proved).
bool separatedByAFacePlane(const btCollisionObjectWrapper* a, const btCollisionObjectWrapper* b, btScalar gap);
// The face that proves it: an index into a's faces, or a's face count plus an index into b's;
// -1 when none does. `hint`, such an index from an earlier step, is tried first: a pair that
// stays apart is usually kept apart by the same face, so its test costs one face instead of
// all of them (and Bullet's separating-axis test, which tries every face and edge pair).
int separatingFace(const btCollisionObjectWrapper* a, const btCollisionObjectWrapper* b, btScalar gap, int hint = -1);

// Where b stands in a's frame and a in b's, as separatingFace computes them from the two world
// transforms. Every leaf pair of two groups has their bodies' transforms: made once for the
// group pair, not twice per leaf pair (a tenth of the test between two tets).
struct RelativePose {
    RelativePose(const btTransform& ta, const btTransform& tb) : bToA(ta.inverseTimes(tb)), aToB(bToA.inverse()) {}
    btTransform bToA, aToB;
};
// separatingFace for hulls a and b (with polyhedral features) placed by `pose`: the same face.
int separatingFace(const btConvexPolyhedron& a, const btConvexPolyhedron& b, const RelativePose& pose, btScalar gap,
                   int hint = -1);

// What a dispatcher with FragmentPairCreateFunc registered (registerGroupShapeAlgorithms) gives
// for contacts between a hull and a fragment's hull, without its table and the casts that
// find out which is the fragment (a caller that knows: a group's leaf against a fragment).
btCollisionAlgorithm* newFragmentPair(btDispatcher* dispatcher, const btCollisionObjectWrapper* a,
                                      const btCollisionObjectWrapper* b);

// For (convex hull, convex hull) contact queries: FragmentPairAlgorithm when either hull is a
// FragmentHull, the collision configuration's own algorithm otherwise (an application's hulls
// are left as they are).
class FragmentPairCreateFunc : public btCollisionAlgorithmCreateFunc {
public:
    btCollisionAlgorithm* CreateCollisionAlgorithm(btCollisionAlgorithmConstructionInfo& ci,
                                                   const btCollisionObjectWrapper* body0,
                                                   const btCollisionObjectWrapper* body1) override;
};

} // namespace shatter
