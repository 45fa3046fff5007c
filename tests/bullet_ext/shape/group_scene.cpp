#include "tests/bullet_ext/shape/group_scene.h"

#include <shatter/bullet_ext/shape/GroupCollisionAlgorithms.h>

#include <algorithm>

namespace shatter::test {

geometry::ConvexPolyhedron boxPrimitive(const Eigen::Vector3d& centre, const Eigen::Vector3d& half) {
    std::vector<Eigen::Vector3d> v;
    for (int i = 0; i < 8; ++i)
        v.push_back(centre + Eigen::Vector3d(i & 1 ? half.x() : -half.x(), i & 2 ? half.y() : -half.y(),
                                             i & 4 ? half.z() : -half.z()));
    // Counter-clockwise seen from outside.
    std::vector<std::vector<int>> f = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    return geometry::ConvexPolyhedron::create(std::move(v), std::move(f), {0, 1, 2, 3, 4, 5, 6, 7}, "test box");
}

geometry::ConvexPolyhedron prismPrimitive(const Eigen::Vector3d& origin, double a, double b, double depth) {
    std::vector<Eigen::Vector3d> v = {{0, 0, 0}, {a, 0, 0}, {0, b, 0}, {0, 0, depth}, {a, 0, depth}, {0, b, depth}};
    for (auto& p : v) p += origin;
    std::vector<std::vector<int>> f = {{0, 2, 1}, {3, 4, 5}, {0, 1, 4, 3}, {1, 2, 5, 4}, {2, 0, 3, 5}};
    return geometry::ConvexPolyhedron::create(std::move(v), std::move(f), {0, 1, 2, 3, 4, 5}, "test prism");
}

Primitives table(double topHalfX, double topHalfZ, double topHalfThickness, double legHalf, double legHeight) {
    Primitives p;
    p.push_back(boxPrimitive({0, legHeight + topHalfThickness, 0}, {topHalfX, topHalfThickness, topHalfZ}));
    for (int sx : {-1, 1})
        for (int sz : {-1, 1})
            p.push_back(boxPrimitive({sx * (topHalfX - legHalf), 0.5 * legHeight, sz * (topHalfZ - legHalf)},
                                     {legHalf, 0.5 * legHeight, legHalf}));
    return p;
}

Primitives lShape() {
    return {boxPrimitive({0.3, 0.05, 0.05}, {0.3, 0.05, 0.05}), boxPrimitive({0.05, 0.05, 0.25}, {0.05, 0.05, 0.15})};
}

Primitives slabFloor(int nx, int nz, double cell) {
    Primitives p;
    for (int i = 0; i < nx; ++i)
        for (int k = 0; k < nz; ++k)
            p.push_back(boxPrimitive({(i - 0.5 * (nx - 1)) * cell, -0.1, (k - 0.5 * (nz - 1)) * cell},
                                     {0.5 * cell, 0.1, 0.5 * cell}));
    return p;
}

BodyFrame toBodyFrame(const Primitives& designPrimitives, double density) {
    geometry::MassProperties total;
    for (const auto& p : designPrimitives) total += p.massProperties(density);
    const auto principal = total.principal();
    Eigen::Isometry3d bodyToDesign = Eigen::Isometry3d::Identity();
    bodyToDesign.linear() = principal.axes;
    bodyToDesign.translation() = total.centerOfMass;
    BodyFrame frame;
    for (const auto& p : designPrimitives) frame.primitives.push_back(p.transformed(bodyToDesign.inverse()));
    frame.bodyToDesign = toBullet(bodyToDesign);
    frame.mass = total.mass;
    frame.inertia = toBullet(principal.moments);
    return frame;
}

std::unique_ptr<btCompoundShape> compoundOf(const Primitives& bodyPrimitives, double margin,
                                            std::vector<std::unique_ptr<btCollisionShape>>& children) {
    auto compound = std::make_unique<btCompoundShape>();
    for (const auto& p : bodyPrimitives) {
        auto hull = std::make_unique<btConvexHullShape>();
        for (const auto& v : p.vertices()) hull->addPoint(toBullet(v), false);
        hull->setMargin(btScalar(margin));
        hull->recalcLocalAabb();
        hull->initializePolyhedralFeatures();
        compound->addChildShape(btTransform::getIdentity(), hull.get());
        children.push_back(std::move(hull));
    }
    return compound;
}

GroupWorld::GroupWorld(bool registerGroupAlgorithms) {
    if (registerGroupAlgorithms) registerGroupShapeAlgorithms(base_.dispatcher);
}

GroupWorld::~GroupWorld() {
    for (auto it = bodies_.rbegin(); it != bodies_.rend(); ++it) base_.world.removeRigidBody(it->get());
}

btRigidBody* GroupWorld::add(std::unique_ptr<btCollisionShape> shape, double mass, const btTransform& pose,
                             const btVector3* inertia, double friction) {
    btVector3 localInertia(0, 0, 0);
    if (mass > 0) {
        if (inertia)
            localInertia = *inertia;
        else
            shape->calculateLocalInertia(btScalar(mass), localInertia);
    }
    auto motion = std::make_unique<btDefaultMotionState>(pose);
    btRigidBody::btRigidBodyConstructionInfo info(btScalar(mass), motion.get(), shape.get(), localInertia);
    info.m_friction = btScalar(friction);
    auto body = std::make_unique<btRigidBody>(info);
    base_.world.addRigidBody(body.get());
    shapes_.push_back(std::move(shape));
    motionStates_.push_back(std::move(motion));
    bodies_.push_back(std::move(body));
    return bodies_.back().get();
}

btRigidBody* GroupWorld::addGroup(const Primitives& designPrimitives, const btTransform& designPose, double margin,
                                  double density) {
    const BodyFrame frame = toBodyFrame(designPrimitives, density);
    auto shape = std::make_unique<GroupShape>(frame.primitives, margin);
    const btVector3 inertia = frame.inertia;
    return add(std::move(shape), density > 0 ? frame.mass : 0.0, designPose * frame.bodyToDesign, &inertia);
}

btRigidBody* GroupWorld::addCompound(const Primitives& designPrimitives, const btTransform& designPose, double margin,
                                     double density) {
    const BodyFrame frame = toBodyFrame(designPrimitives, density > 0 ? density : 1.0);
    std::vector<std::unique_ptr<btCollisionShape>> children;
    auto compound = compoundOf(frame.primitives, margin, children);
    for (auto& c : children) shapes_.push_back(std::move(c));
    const btVector3 inertia = frame.inertia;
    return add(std::move(compound), density > 0 ? frame.mass : 0.0, designPose * frame.bodyToDesign, &inertia);
}

btRigidBody* GroupWorld::addStaticPlane(const btVector3& normal, double constant) {
    return add(std::make_unique<btStaticPlaneShape>(normal, btScalar(constant)), 0.0, btTransform::getIdentity());
}

btRigidBody* GroupWorld::addStaticGroup(const Primitives& primitives, const btTransform& pose, double margin) {
    return add(std::make_unique<GroupShape>(primitives, margin), 0.0, pose);
}

void GroupWorld::step(int n) { base_.step(n); }

namespace {

template <class F>
void forEachManifold(btCollisionDispatcher& dispatcher, const btRigidBody* a, const btRigidBody* b, F f) {
    for (int m = 0; m < dispatcher.getNumManifolds(); ++m) {
        const btPersistentManifold* manifold = dispatcher.getManifoldByIndexInternal(m);
        const bool ab = manifold->getBody0() == a && manifold->getBody1() == b;
        const bool ba = manifold->getBody0() == b && manifold->getBody1() == a;
        if (ab || ba) f(*manifold, ab);
    }
}

} // namespace

btVector3 GroupWorld::contactNormalOn(const btRigidBody* body, const btRigidBody* other) {
    btVector3 sum(0, 0, 0);
    forEachManifold(base_.dispatcher, body, other, [&](const btPersistentManifold& m, bool bodyIsBody0) {
        for (int i = 0; i < m.getNumContacts(); ++i) {
            const btManifoldPoint& p = m.getContactPoint(i);
            // Bullet's normal points from body1 towards body0; weighting by the impulse the
            // solver applied leaves out speculative points that carry no load.
            sum += (bodyIsBody0 ? p.m_normalWorldOnB : -p.m_normalWorldOnB) * p.getAppliedImpulse();
        }
    });
    return sum.length2() > 0 ? sum.normalized() : sum;
}

int GroupWorld::contactCount(const btRigidBody* a, const btRigidBody* b) {
    int count = 0;
    forEachManifold(base_.dispatcher, a, b, [&](const btPersistentManifold& m, bool) {
        for (int i = 0; i < m.getNumContacts(); ++i)
            if (m.getContactPoint(i).getDistance() <= btScalar(0.005)) ++count;
    });
    return count;
}

double restHeight(const BodyFrame& frame, double gap) { return double(frame.bodyToDesign.getOrigin().y()) + gap; }

BoxStack stackOfBoxes(GroupWorld& w) {
    w.addStaticGroup(slabFloor(4, 4, 0.25));
    const Primitives box = {boxPrimitive({0, 0.1, 0}, {0.1, 0.1, 0.1})};
    const btVector3 axis = btVector3(1, 2, 3).normalized();
    std::vector<btRigidBody*> bodies;
    for (int k = 0; k < 3; ++k)
        bodies.push_back(w.addGroup(box, btTransform(btQuaternion(axis, btScalar(0.05 * k)),
                                                     btVector3(btScalar(0.01 * k), btScalar(0.001 + 0.2005 * k), 0)),
                                    0.004));
    w.step(480);
    BoxStack s;
    for (const btRigidBody* b : bodies) {
        s.heights.push_back(double(b->getCenterOfMassPosition().y()));
        s.fastest = std::max({s.fastest, double(b->getLinearVelocity().length()), double(b->getAngularVelocity().length()) * 0.1});
    }
    return s;
}

} // namespace shatter::test
