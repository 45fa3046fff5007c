#pragma once
// Contacts between two small convex polyhedra (a group's leaf hull, a fragment's hull, a box):
// Bullet's separating-axis test and face clipping (btPolyhedralContactClipping), with the
// separating-axis test done in one hull's frame.
//
// Bullet's own test (findSeparatingAxis) projects both hulls on every candidate axis, and each
// projection maps every vertex to world space again: for two tets, 44 axes × 8 vertex
// transforms, plus an inner-box bound per axis. In the lattice wall's worst frames that test,
// on debris against the wall's leaves, was a quarter of the instructions. Here each vertex is
// mapped once and each axis costs only dot products. Two hulls of at most 8 vertices each (a
// lattice's tets, boxes) try every axis four at a time in lanes (AxisLanes.h), settled in the
// one-axis order (a group's leaf hull keeps its vertices and face normals in lanes, HullLanes.h;
// other hulls are put in lanes per pair); when either hull has more than 10 vertices, four axes
// at a time are first bounded from a few vertices of each hull (AxisLanes.h, in the same
// arithmetic), so that most of the ~1,700 edge pairs of a fragment's many-sided hull against a
// primitive are never tried: their overlap provably exceeds the least so far. Everything else
// is Bullet's arithmetic, operation for operation (the axes, their order, signs and choice,
// the extra edge-edge point), so the contacts are Bullet's bit for bit (PolyhedronContacts
// test): the chaotic lattice scenes break the same.
#include <BulletCollision/CollisionShapes/btConvexPolyhedron.h>
#include <BulletCollision/NarrowPhaseCollision/btDiscreteCollisionDetectorInterface.h>

namespace shatter {

// The separating-axis test of btPolyhedralContactClipping::findSeparatingAxis: false when an
// axis separates the two hulls (placed by `ta` and `tb`); otherwise true, with `normal` (world)
// the axis of least overlap, pointing from b to a. When that axis is an edge pair, adds the
// edges' closest-point contact to `result`, as Bullet does.
// `separating` (optional) remembers a separating axis between steps: in, one that separated
// the pair before (−1: none), tried first; out, the one that separates them now (unchanged
// when none does). Axes are numbered in the order the test tries them: a's faces, b's faces,
// then a's unique edges times b's. Any separating axis gives the same answer (false, nothing
// added), so the hint changes no result, only the cost: a pair that stays a hair apart (debris
// against the wall tets it broke from) is usually kept apart by the same axis, and the test
// then costs one axis instead of up to 44.
bool leastOverlapAxis(const btConvexPolyhedron& a, const btTransform& ta, const btConvexPolyhedron& b,
                      const btTransform& tb, btVector3& normal, btDiscreteCollisionDetectorInterface::Result& result,
                      int* separating = nullptr);

// What btConvexConvexAlgorithm adds for two hulls with polyhedral features and the
// separating-axis test on: the test above, then b's face most facing a clipped against a's
// face, each clipped point within `threshold` (the manifold's contact breaking threshold)
// added to `result`. Only where the hulls overlap: margins are not applied. False when an axis
// separates them (nothing added). `separating` as for leastOverlapAxis.
bool polyhedronContacts(const btConvexPolyhedron& a, const btTransform& ta, const btConvexPolyhedron& b,
                        const btTransform& tb, btScalar threshold, btDiscreteCollisionDetectorInterface::Result& result,
                        int* separating = nullptr);

// One contact between a hull (polyhedral features, margin `hullMargin`) and a box (half
// extents `half`, its surface; a btBoxShape's margin is inside them), with Bullet's GJK
// conventions (a point a margin from the hull, the margin counted in the distance) at the cost
// of a separating-axis test in the box's frame: the axis of largest gap (least overlap) among
// the box's faces, the hull's faces and their edge pairs is the normal; the point is the middle
// of the hull's vertices deepest along it (a box face), of the box's corners deepest along it
// (a hull face), or where the hull's deepest edge passes closest to the box's (an edge pair).
// False when the gap exceeds the margin and `threshold` (no contact, as GJK would give none).
struct BoxContact {
    btVector3 normal; // world, from the box towards the hull
    btVector3 onBox;  // world, the point on the box's surface
    btScalar distance; // < 0: penetrating, the hull's margin included
};
bool hullBoxContact(const btConvexPolyhedron& hull, const btTransform& hullPose, btScalar hullMargin,
                    const btVector3& half, const btTransform& boxPose, btScalar threshold, BoxContact& contact);

// The box [-h, h] as polyhedral features (faces counter-clockwise seen from outside, as
// Bullet's clipping expects): a btBoxShape's own are built only on request, on the shape.
btConvexPolyhedron boxPolyhedron(const btVector3& halfExtents);

} // namespace shatter
