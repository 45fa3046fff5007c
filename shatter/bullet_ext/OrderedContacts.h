#pragma once
// The order Bullet's solver and Shatter's contact snapshot take the contact manifolds in, made
// independent of the manifolds' places in the dispatcher (HullPairContacts::keepEmptyLeafManifolds
// off). Bullet's sequential-impulse solver takes the points manifold by manifold, in the order
// its island manager leaves them: the dispatcher's array, where every manifold made or freed
// moves another (releaseManifold fills the place with the last one), sorted by island with an
// unstable quicksort. So an empty manifold, which holds nothing to solve, still decides in
// which order the others are solved, and a group pair could not free its empty leaf manifolds
// without moving every result. Here the manifolds with points are taken by (body0, body1) —
// the broadphase's unique ids, given in the order bodies enter the world — and then by their
// first point's shape identifiers (a group's leaf pair: partId -1 and the primitive on each side),
// which tell a group pair's leaf manifolds apart. Ties keep the dispatcher's order (stable).
#include <BulletDynamics/ConstraintSolver/btConstraintSolver.h>

#include <vector>

class btPersistentManifold;

namespace shatter {

// Whether manifold `a` (with points) comes before `b` (with points).
bool contactPairBefore(const btPersistentManifold* a, const btPersistentManifold* b);

// The manifolds with points, in that order.
void orderContactManifolds(btPersistentManifold* const* manifolds, int count, std::vector<btPersistentManifold*>& ordered);

// Passes each group to `inner` with its manifolds in that order in a world that takes its
// contacts in it (dispatcherOrdersContacts, AttachedWorld.h), and as they come in another.
// Solving islands apart or together gives the same bits (they share no body), so the batches
// Bullet forms from manifold counts do not matter.
class OrderedContactSolver : public btConstraintSolver {
public:
    explicit OrderedContactSolver(btConstraintSolver& inner) : inner_(&inner) {}
    btConstraintSolver& inner() const { return *inner_; }

    void prepareSolve(int numBodies, int numManifolds) override { inner_->prepareSolve(numBodies, numManifolds); }
    btScalar solveGroup(btCollisionObject** bodies, int numBodies, btPersistentManifold** manifolds, int numManifolds,
                        btTypedConstraint** constraints, int numConstraints, const btContactSolverInfo& info,
                        btIDebugDraw* debugDrawer, btDispatcher* dispatcher) override;
    void allSolved(const btContactSolverInfo& info, btIDebugDraw* debugDrawer) override { inner_->allSolved(info, debugDrawer); }
    void reset() override { inner_->reset(); }
    btConstraintSolverType getSolverType() const override { return inner_->getSolverType(); }

private:
    btConstraintSolver* inner_;
};

} // namespace shatter
