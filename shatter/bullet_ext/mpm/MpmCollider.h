#pragma once
// A Bullet collision object as an obstacle of the 2D MPM crack solver, seen through its
// signed distance:
//
//   auto ground = std::make_shared<shatter::MpmCollider>(groundBody);
//   solver.addCollider(ground);                 // shatter::mpm::Solver2D
//   world.stepSimulation(dt); ground->update(); solver.advance(dt);   // per frame, if it moves
//
// The simulation plane. An MPM point (x, y) is the world point plane·(x, y, 0): by default
// (identity) MPM x, y are world x, y at z = 0, so Bullet's y-up world and the MPM gravity
// (0, −9.81) agree. Any other rigid transform (finite, orthonormal basis) places the plane
// elsewhere; its basis columns are the MPM x axis, the MPM y axis and the plane normal.
//
// What the solver sees. The signed distance is the 3D signed distance from the world point
// to the surface Bullet itself collides with (margins included: a btBoxShape's margin lies
// inside its extents, so the box has its full extents with edges rounded by the margin; a
// btSphereShape is all margin, so it is the exact sphere; a btConvexHullShape is the hull
// grown by its margin). Its zero set in the plane is exactly the object's cross-section, so
// the inside/outside test the solver makes is exact; away from the surface the value is the
// 3D distance, not the distance within the plane (they agree for objects whose surface
// crosses the plane at right angles, e.g. a box or cylinder along the plane normal, a sphere
// centred in it). The normal is the in-plane part of the 3D outward normal, normalised. The
// object should therefore cross the plane with surfaces that are not parallel to it where the
// material touches it (a slab lying in the plane has no in-plane normal; see normal()).
//
// Shapes: btStaticPlaneShape and btSphereShape (exact formulas), every other convex shape
// through btGjkEpaSolver2::SignedDistance (single-precision Bullet, tested: outside flat
// faces to float rounding, outside curved ones to ~1e-4 m with normals within ~1.5°;
// inside, where EPA answers, to its 1e-4 m tolerance on flat faces and to ~0.2% of the size
// on curved ones, which EPA sees as a polytope), btCompoundShape (minimum over its children, recursively) and shatter::GroupShape
// (minimum over its primitives). The minimum is the exact distance outside a union and has
// the exact sign inside it. Anything else (triangle meshes, heightfields, ...) is rejected
// with shatter::InputError naming the shape type.
//
// Velocity: the object's rigid velocity at the point, v + ω × (x − centre of mass), projected
// into the plane, so a moving or spinning Bullet body drives the material it touches (the
// solver applies it in Collider::project). btRigidBody velocities are used for rigid bodies;
// other collision objects use their interpolation velocities (zero unless set).
//
// Snapshot. The pose, the velocity and the list of convex pieces are read at construction and
// by update(); queries use that snapshot only, so the solver's threads never read Bullet
// state while it changes, and an MPM advance sees one fixed pose. Call update() after each
// world.stepSimulation() for objects that move; within one advance the object stands still
// at that pose while its surface velocity acts on the material. The collision object and its
// shapes must outlive this collider.
#include <shatter/plugin/mpm/Collider.h>

#include <BulletCollision/CollisionDispatch/btCollisionObject.h>
#include <BulletCollision/CollisionShapes/btConvexShape.h>
#include <LinearMath/btTransform.h>

#include <string>
#include <vector>

namespace shatter {

class MpmCollider final : public mpm::Collider {
public:
    // Throws shatter::InputError for an unsupported shape (naming its type and where it sits
    // in a compound), a non-finite pose or velocity, a plane transform that is not finite and
    // rigid, a plane shape parallel to the simulation plane, or a negative friction.
    explicit MpmCollider(const btCollisionObject& object, const btTransform& plane = btTransform::getIdentity(),
                                  double friction = 0);

    // Reads the object's pose, velocity and (compound) shape again. Same errors as the
    // constructor. Not thread-safe against queries: call it between solver advances.
    void update();

    struct Sample {
        double distance = 0;             // m, negative inside
        mpm::Vec2 normal{0.0, 1.0};      // outward, unit length, in MPM coordinates
    };
    // Signed distance and normal at an MPM point in one evaluation.
    Sample sample(const mpm::Vec2& p) const;

    // mpm::Collider (thread-safe, as the solver requires).
    double signedDistance(const mpm::Vec2& p) const override;
    // Where the in-plane part of the 3D normal vanishes (the nearest surface is parallel to
    // the plane, or the point is at a sphere's centre), the normal points away from the
    // nearest piece's centre within the plane; (0, 1) if that is undefined too.
    mpm::Vec2 normal(const mpm::Vec2& p) const override;
    mpm::Vec2 velocity(const mpm::Vec2& p) const override;

    // The world point of an MPM point, and an MPM point of a world point (dropping the
    // component along the plane normal).
    btVector3 toWorld(const mpm::Vec2& p) const;
    mpm::Vec2 toPlane(const btVector3& world) const;

    const btCollisionObject& object() const { return object_; }
    const btTransform& plane() const { return plane_; }
    // Convex pieces (plus planes) the object was split into at the last update.
    int pieceCount() const { return int(pieces_.size()); }

private:
    struct Piece {
        const btConvexShape* convex = nullptr; // null for a plane piece
        btTransform pose;                      // world pose of the convex shape
        btScalar sphereRadius = -1;            // >= 0: a btSphereShape, measured exactly
        btVector3 planeNormal{0, 0, 0};        // plane piece: world unit normal
        btScalar planeOffset = 0;              // plane piece: normal · x on the plane
        btVector3 aabbMin{0, 0, 0}, aabbMax{0, 0, 0}; // convex piece: world box, margins included
    };
    struct Nearest {
        double distance;
        btVector3 normal; // world, outward
        int piece;
    };

    void addPieces(const btCollisionShape& shape, const btTransform& pose, const std::string& where);
    Nearest nearest(const btVector3& world) const;
    mpm::Vec2 inPlane(const btVector3& worldVector) const;

    const btCollisionObject& object_;
    btTransform plane_;
    std::vector<Piece> pieces_;
    btVector3 linearVelocity_{0, 0, 0}, angularVelocity_{0, 0, 0}, centreOfMass_{0, 0, 0};
};

} // namespace shatter
