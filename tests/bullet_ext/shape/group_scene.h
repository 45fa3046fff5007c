#pragma once
// Test scenes for the group shape: box and prism primitives, a table and an L made of them,
// and a plain Bullet world (y up) with the group shape's algorithms registered, as an
// application would have it once shatter::Plugin is attached.
#include <shatter/bullet_ext/Convert.h>
#include <shatter/bullet_ext/shape/GroupShape.h>
#include "tests/support/TestWorld.h"

#include <btBulletDynamicsCommon.h>

#include <memory>
#include <vector>

namespace shatter::test {

using Primitives = std::vector<geometry::ConvexPolyhedron>;

// The collision margin the group-shape tests give their group shapes.
constexpr double kGroupMargin = 0.04;

// Axis-aligned box with the given centre and half extents.
geometry::ConvexPolyhedron boxPrimitive(const Eigen::Vector3d& centre, const Eigen::Vector3d& half);
// Triangular prism along z: right triangle (0,0), (a,0), (0,b) in xy, z from 0 to depth, moved by `origin`.
geometry::ConvexPolyhedron prismPrimitive(const Eigen::Vector3d& origin, double a, double b, double depth);

// Table (y up): a top of size 2·topHalf.x × 2·topThickness × 2·topHalf.y, and four legs of
// square section 2·legHalf and height legHeight under its corners. Lowest point at y = 0.
Primitives table(double topHalfX = 0.4, double topHalfZ = 0.3, double topHalfThickness = 0.025, double legHalf = 0.03,
                 double legHeight = 0.5);
// An L lying flat: a bar along x and a shorter one along z, both 0.1 m thick. Lowest point at y = 0.
Primitives lShape();
// A slab floor of nx × nz boxes (each cell × 0.2 × cell), top face at y = 0.
Primitives slabFloor(int nx, int nz, double cell);

// The primitives moved into their centre-of-mass principal frame, and where that frame lies
// in the coordinates they were given in.
struct BodyFrame {
    Primitives primitives;
    btTransform bodyToDesign;
    double mass;            // at the density used
    btVector3 inertia;      // principal moments
};
BodyFrame toBodyFrame(const Primitives& designPrimitives, double density = 500.0);

// The same primitives as Bullet's compound of convex hulls (what an app would do without Shatter).
std::unique_ptr<btCompoundShape> compoundOf(const Primitives& bodyPrimitives, double margin,
                                            std::vector<std::unique_ptr<btCollisionShape>>& children);

class GroupWorld {
public:
    explicit GroupWorld(bool registerGroupAlgorithms = true);
    ~GroupWorld();
    GroupWorld(const GroupWorld&) = delete;
    GroupWorld& operator=(const GroupWorld&) = delete;

    // Takes ownership of the shape. mass 0 = static. Inertia from the shape unless given.
    btRigidBody* add(std::unique_ptr<btCollisionShape> shape, double mass, const btTransform& pose,
                     const btVector3* inertia = nullptr, double friction = 0.6);
    // A dynamic group body whose design-coordinate primitives are placed by designPose.
    btRigidBody* addGroup(const Primitives& designPrimitives, const btTransform& designPose, double margin = 0.04,
                          double density = 500.0);
    // The same geometry as a compound of hulls (static if density == 0).
    btRigidBody* addCompound(const Primitives& designPrimitives, const btTransform& designPose, double margin = 0.04,
                             double density = 500.0);
    btRigidBody* addStaticPlane(const btVector3& normal = btVector3(0, 1, 0), double constant = 0.0);
    btRigidBody* addStaticGroup(const Primitives& primitives, const btTransform& pose = btTransform::getIdentity(),
                                double margin = 0.04);

    // Keeps `data` (e.g. a btTriangleMesh a shape points into) alive as long as the world.
    template <class T>
    T& keep(std::unique_ptr<T> data) {
        T& ref = *data;
        kept_.push_back(std::shared_ptr<void>(std::move(data)));
        return ref;
    }

    // n steps of 1/240 s.
    void step(int n);

    btDiscreteDynamicsWorld& world() { return base_.world; }
    btCollisionDispatcher& dispatcher() { return base_.dispatcher; }
    // Contact normal on `body`, pointing out of the other body (towards `body`): the mean of
    // the pair's manifold normals weighted by the impulse the solver applied at each point
    // in the last step; zero if they do not touch.
    btVector3 contactNormalOn(const btRigidBody* body, const btRigidBody* other);
    int contactCount(const btRigidBody* a, const btRigidBody* b);

private:
    std::vector<std::shared_ptr<void>> kept_; // destroyed last
    TestWorld base_;
    std::vector<std::unique_ptr<btCollisionShape>> shapes_;
    std::vector<std::unique_ptr<btMotionState>> motionStates_;
    std::vector<std::unique_ptr<btRigidBody>> bodies_;
};

// Centre-of-mass height above y = 0 for a body resting upright whose design primitives have
// their lowest point at y = 0, resting `gap` above the ground.
double restHeight(const BodyFrame& frame, double gap);

// A stack of three group boxes dropped on a slab floor in `w`, 2 s: each box's final height and
// the largest of the boxes' speeds (linear, and angular times 0.1 m) at the end.
struct BoxStack {
    std::vector<double> heights;
    double fastest = 0;
};
BoxStack stackOfBoxes(GroupWorld& w);

} // namespace shatter::test
