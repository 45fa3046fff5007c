#pragma once
// The collision shape of a convex lattice piece (source 002 §3: a fragment collides as "a
// convex hull where the piece is convex"). A plain btConvexHullShape over the piece's nodes
// takes Bullet's own convex algorithms (GJK and EPA against hulls, the plane algorithm against
// the ground), which cost a fraction of the group shape's per-primitive separating-axis test:
// after an impact hundreds of single-tet fragments are in contact at once.
#include <shatter/bullet_ext/shape/GroupShape.h>

#include <BulletCollision/CollisionShapes/btConvexHullShape.h>

#include <memory>

namespace shatter {

// Bullet's hull box is the box of its body-frame box turned with the body: up to √3 times
// the hull's own extent per axis for a turned tet; and the world grows every box by Bullet's
// global contact breaking threshold (2 cm), more than a 5 cm tet's own threshold (under a
// millimetre: its angular motion disc times the global one). In a heap of fragments every box
// pair is a narrowphase pair (the wall's heap: 25,000 pairs for 300 pieces), so the box the
// world sees is the turned points' exact box grown by the margin and the hull's own contact
// breaking threshold only: getAabb returns that, less the growth the world adds back. (So
// getAabb itself may be smaller than the hull by up to 2 cm per side: read a fragment's
// box from its broadphase proxy.)
class FragmentHull : public btConvexHullShape {
public:
    void getAabb(const btTransform& t, btVector3& aabbMin, btVector3& aabbMax) const override;
    // Bullet's own goes through getAabb (to a bounding sphere): from the cached local box here.
    btScalar getAngularMotionDisc() const override;
    // The hull's polyhedral features built in place by build(btConvexPolyhedron&), from empty:
    // setPolyhedralFeatures copies a whole polyhedron (an allocation per face, then the
    // original's freed). They keep their lanes (HullLanes.h), as a group's leaf hulls do,
    // made once build returns: the face-plane and separating-axis tests of a fragment against
    // a group's leaves read them every step, and put a plain hull's into lanes per pair.
    template <class Build>
    void buildFeatures(Build&& build) {
        build(emptyFeatures());
        featuresSet();
    }
    // Bullet's, with the lanes made again (Bullet assigns the new features over the kept ones).
    void setPolyhedralFeatures(btConvexPolyhedron& polyhedron) override;

private:
    // Two steps a caller could split (empty lanes: wrong separating axes, no error), hence
    // private: buildFeatures runs both.
    btConvexPolyhedron& emptyFeatures();
    void featuresSet();
};

// Whether `shape` is a lattice fragment's hull.
bool isFragmentHull(const btCollisionShape* shape);

// A hull over the vertices of every primitive of `group` (the body frame of the body that
// carries it), each vertex once. Its margin is `margin` (m), the margin the group shape puts
// around each primitive, so the piece collides the same either way; Bullet's default hull
// margin (4 cm) would grow a 10 cm fragment by almost half. With polyhedral features (a
// group's child's for a single tet, primitiveFeatures; convexHullOf's otherwise), so hull-hull
// pairs make full face-clipped manifolds.
// `primitives` are those of the group shape the hull stands for (VisualBody::shapePrimitives:
// the group need not be built).
std::unique_ptr<btConvexHullShape> makeFragmentHull(const std::vector<geometry::ConvexPolyhedron>& primitives,
                                                    double margin);

// The hull of a fracture shard of several primitives: only the hull's own vertices as points
// (Bullet's GJK support and getAabb visit every point at every step; most corners of a shard's
// primitives lie inside its hull or on its faces), and Bullet's polyhedral features built at a
// fraction of Bullet's cost (convexHullOf). `shrink` (0 to 1) moves every point that much of
// the way towards the frame's origin (a body's centre of mass, inside the hull): each face
// moves in by that share of its distance from the origin. Margin as in makeFragmentHull.
// Throws shatter::InputError when the primitives span no volume.
// `primitives` are those of the group shape the hull stands for (VisualBody::shapePrimitives:
// the group need not be built).
std::unique_ptr<btConvexHullShape> makeShardHull(const std::vector<geometry::ConvexPolyhedron>& primitives,
                                                 double margin, double shrink);

} // namespace shatter
