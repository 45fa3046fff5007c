// shatter::MpmCollider: Bullet collision objects as obstacles of the 2D MPM solver.
// Distances and normals against analytic values, velocities of moving bodies, bad input, and
// MPM material dropped onto Bullet bodies.
//
// Tolerances. Outside a convex shape the distance comes from GJK on single-precision
// (float) Bullet: measured errors are below 5e-7 m for coordinates of order 1 m, asserted at
// 1e-5 m. Inside, it comes from EPA, whose single-precision accuracy is EPA_ACCURACY =
// 1e-4 (measured 6e-5 m): asserted at 2e-4 m. Normals: 1e-4 outside, 2e-3 inside.
#include <shatter/bullet_ext/mpm/MpmCollider.h>
#include <shatter/bullet_ext/shape/GroupShape.h>
#include "tests/bullet_ext/shape/group_scene.h"
#include <shatter/plugin/common/InputError.h>
#include <shatter/plugin/mpm/Diagnostics.h>
#include <shatter/plugin/mpm/Solver2D.h>

#include <BulletCollision/CollisionShapes/btTriangleMesh.h>
#include <btBulletDynamicsCommon.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cmath>
#include <limits>
#include <memory>
#include <numbers>

namespace shatter {
namespace {

using mpm::Vec2;

constexpr double kOutside = 1e-5; // m, GJK in float
constexpr double kInside = 2e-4;  // m, EPA in float (EPA_ACCURACY 1e-4)

btTransform pose(double x, double y, double z, double angleAboutZ = 0) {
    return btTransform(btQuaternion(btVector3(0, 0, 1), btScalar(angleAboutZ)),
                       btVector3(btScalar(x), btScalar(y), btScalar(z)));
}

btCollisionObject objectWith(btCollisionShape& shape, const btTransform& t) {
    btCollisionObject o;
    o.setCollisionShape(&shape);
    o.setWorldTransform(t);
    return o;
}

// Signed distance of a box of half extents h (centred at the origin), exact.
double boxDistance(const Vec2& q, const Vec2& h) {
    const Vec2 d = q.cwiseAbs() - h;
    return d.cwiseMax(0.0).norm() + std::min(std::max(d.x(), d.y()), 0.0);
}

// Samples on a regular lattice over [lo, hi]².
std::vector<Vec2> lattice(double lo, double hi, int n) {
    std::vector<Vec2> pts;
    for (int i = 0; i <= n; ++i)
        for (int j = 0; j <= n; ++j) pts.emplace_back(lo + (hi - lo) * i / n, lo + (hi - lo) * j / n);
    return pts;
}

TEST(MpmCollider, StaticPlaneIsExact) {
    // Ground y = 0.5 (normal +y, constant 0.5), then the same plane tilted by 20° about z.
    btStaticPlaneShape ground(btVector3(0, 1, 0), 0.5f);
    btCollisionObject flat = objectWith(ground, btTransform::getIdentity());
    MpmCollider c(flat);
    for (const Vec2& p : lattice(-2, 2, 8)) {
        EXPECT_NEAR(c.signedDistance(p), p.y() - 0.5, 1e-6) << p.transpose();
        EXPECT_NEAR((c.normal(p) - Vec2(0, 1)).norm(), 0, 1e-7);
        EXPECT_EQ(c.velocity(p), Vec2::Zero());
    }
    const double a = 20 * std::numbers::pi / 180;
    btCollisionObject tilted = objectWith(ground, pose(0.3, -0.2, 0, a));
    MpmCollider t(tilted);
    const Vec2 n(-std::sin(a), std::cos(a)), o(0.3, -0.2);
    for (const Vec2& p : lattice(-2, 2, 8)) {
        EXPECT_NEAR(t.signedDistance(p), (p - o).dot(n) - 0.5, 2e-6) << p.transpose();
        EXPECT_NEAR((t.normal(p) - n).norm(), 0, 1e-6);
    }
}

TEST(MpmCollider, SimulationPlaneMapsMpmAxesIntoTheWorld) {
    // The MPM plane turned 90° about world y and moved to z = 2: basis columns MPM x →
    // (0, 0, −1), MPM y → (0, 1, 0), normal → (1, 0, 0), so MPM (x, y) = world (0, y, 2 − x).
    const btTransform plane(btQuaternion(btVector3(0, 1, 0), btScalar(std::numbers::pi / 2)), btVector3(0, 0, 2));
    btStaticPlaneShape wall(btVector3(0, 0, 1), 2.5f); // world z >= 2.5 is free
    btCollisionObject o = objectWith(wall, btTransform::getIdentity());
    MpmCollider c(o, plane);
    for (const Vec2& p : lattice(-2, 2, 8)) {
        EXPECT_NEAR((c.toWorld(p) - btVector3(0, btScalar(p.y()), btScalar(2 - p.x()))).length(), 0, 1e-6);
        EXPECT_NEAR((c.toPlane(c.toWorld(p)) - p).norm(), 0, 1e-6);
        // z − 2.5 = (2 − x) − 2.5, free towards −x.
        EXPECT_NEAR(c.signedDistance(p), -0.5 - p.x(), 1e-6);
        EXPECT_NEAR((c.normal(p) - Vec2(-1, 0)).norm(), 0, 1e-6);
    }
}

TEST(MpmCollider, BoxMatchesTheRoundedBoxBulletCollidesWith) {
    // btBoxShape's margin (0.04 m) lies inside its extents: the surface is the full box with
    // edges rounded by the margin, i.e. distance = box(h − m) distance − m. The box reaches
    // 2 m to either side of the plane, so its ±z faces are never the nearest (see the
    // header: a face parallel to the plane has no in-plane normal).
    const Vec2 half(1.0, 0.5);
    btBoxShape box(btVector3(1.0f, 0.5f, 2.0f));
    const double m = box.getMargin();
    ASSERT_NEAR(m, 0.04, 1e-7);
    for (double angle : {0.0, 30 * std::numbers::pi / 180}) {
        const Vec2 centre(0.2, 1.0);
        btCollisionObject o = objectWith(box, pose(centre.x(), centre.y(), 0, angle));
        MpmCollider c(o);
        const Eigen::Rotation2Dd toLocal(-angle);
        int inside = 0, outside = 0;
        for (const Vec2& p : lattice(-1.5, 2.5, 40)) {
            const Vec2 q = toLocal * (p - centre);
            const double exact = boxDistance(q, half - Vec2::Constant(m)) - m;
            const auto s = c.sample(p);
            EXPECT_NEAR(s.distance, c.signedDistance(p), 0);
            EXPECT_NEAR(s.distance, exact, exact < 0 ? kInside : kOutside) << p.transpose();
            (exact < 0 ? inside : outside) += 1;
            // Normals where the nearest feature is a face (not within a margin of an edge).
            const Vec2 e = q.cwiseAbs() - half + Vec2::Constant(m);
            if (e.x() > 0 && e.y() > 0) continue;
            // Skip points equidistant from two faces (adjacent or opposite).
            if (std::abs(e.x() - e.y()) < 1e-3 || std::abs(q.x()) < 1e-3 || std::abs(q.y()) < 1e-3) continue;
            const Vec2 localNormal = e.x() > e.y() ? Vec2(q.x() > 0 ? 1 : -1, 0) : Vec2(0, q.y() > 0 ? 1 : -1);
            EXPECT_NEAR((s.normal - Eigen::Rotation2Dd(angle) * localNormal).norm(), 0, exact < 0 ? 2e-3 : 1e-4)
                << p.transpose();
        }
        EXPECT_GT(inside, 100);
        EXPECT_GT(outside, 100);
    }
}

TEST(MpmCollider, ConvexHullIsGrownByItsMargin) {
    // A btConvexHullShape's margin lies outside its points: the hull of the box corners
    // (half 1 × 0.5, 2 m either side of the plane) with margin 0.04 m is that box grown by a
    // rounded 0.04 m: distance = box distance − m, exactly, outside and inside.
    btConvexHullShape hull;
    for (int k = 0; k < 8; ++k)
        hull.addPoint(btVector3(k & 1 ? 1.0f : -1.0f, k & 2 ? 0.5f : -0.5f, k & 4 ? 2.0f : -2.0f), k == 7);
    hull.setMargin(0.04f);
    const Vec2 centre(-0.3, 0.4);
    const double angle = -40 * std::numbers::pi / 180;
    btCollisionObject o = objectWith(hull, pose(centre.x(), centre.y(), 0, angle));
    MpmCollider c(o);
    const Eigen::Rotation2Dd toLocal(-angle);
    for (const Vec2& p : lattice(-2, 1.5, 35)) {
        const double exact = boxDistance(toLocal * (p - centre), Vec2(1, 0.5)) - 0.04;
        EXPECT_NEAR(c.signedDistance(p), exact, exact < 0 ? kInside : kOutside) << p.transpose();
    }
}

TEST(MpmCollider, CurvedShapesAreExactOutsideAndApproximateDeepInside) {
    // A cylinder along z (across the plane), radius 0.5: its cross-section is a disc. Outside
    // and within the margin shell GJK answers, and on a curved surface it stops at its
    // tolerance GJK_ACCURACY = 1e-4 (relative to the squared distance; measured errors up to
    // 1.1e-4 m at 0.6 m away): asserted at 2e-4 m, with normals within 0.05 (3°; measured
    // 0.025) near the surface (within 0.1 m), where the solver uses them: GJK's normal on a
    // curved surface is that of its last simplex. Deeper inside, EPA measures the depth on
    // the polytope it builds around the curved surface: within 1% of the radius (measured
    // 0.2%, printed), the sign exact.
    btCylinderShapeZ cylinder(btVector3(0.5f, 0.5f, 1.0f));
    const double m = cylinder.getMargin();
    btCollisionObject o = objectWith(cylinder, pose(0.1, 0.2, 0));
    MpmCollider c(o);
    double worstDeep = 0;
    for (const Vec2& p : lattice(-1, 1.2, 44)) {
        const double r = (p - Vec2(0.1, 0.2)).norm(), exact = r - 0.5;
        const double d = c.signedDistance(p);
        if (exact > -m) {
            EXPECT_NEAR(d, exact, 2e-4) << p.transpose();
        } else {
            EXPECT_LT(d, 0) << p.transpose();
            EXPECT_NEAR(d, exact, 0.01 * 0.5) << p.transpose();
            worstDeep = std::max(worstDeep, std::abs(d - exact));
        }
        if (std::abs(exact) < 0.1 && exact > -m) {
            EXPECT_NEAR((c.normal(p) - (p - Vec2(0.1, 0.2)) / r).norm(), 0, 0.05) << p.transpose();
        }
    }
    std::printf("cylinder: worst error deep inside %.4f m\n", worstDeep);
}

TEST(MpmCollider, SphereIsAllMarginAndExact) {
    btSphereShape sphere(0.7f);
    const Vec2 centre(0.3, 0.9);
    btCollisionObject o = objectWith(sphere, pose(centre.x(), centre.y(), 0));
    MpmCollider c(o);
    for (const Vec2& p : lattice(-1, 2, 30)) {
        const double r = (p - centre).norm();
        if (r < 1e-3) continue; // the centre: below
        EXPECT_NEAR(c.signedDistance(p), r - 0.7, kOutside) << p.transpose();
        EXPECT_NEAR((c.normal(p) - (p - centre) / r).norm(), 0, 1e-4) << p.transpose();
    }
    // At the centre (exact formula: EPA would approximate the sphere by a polytope).
    EXPECT_NEAR(c.signedDistance(centre), -0.7, 1e-6);
    EXPECT_NEAR(c.normal(centre).norm(), 1, 1e-9);
}

TEST(MpmCollider, SphereOffThePlaneIsCutToItsCrossSection) {
    // Centre 0.4 m in front of the plane: the cross-section is a circle of radius
    // √(0.7² − 0.4²); the zero set is there, the value is the 3D distance, the normal radial.
    btSphereShape sphere(0.7f);
    btCollisionObject o = objectWith(sphere, pose(0, 0, 0.4));
    MpmCollider c(o);
    const double section = std::sqrt(0.49 - 0.16);
    for (int k = 0; k < 12; ++k) {
        const double a = 2 * std::numbers::pi * k / 12;
        const Vec2 dir(std::cos(a), std::sin(a));
        EXPECT_NEAR(c.signedDistance(section * dir), 0, kOutside);
        EXPECT_LT(c.signedDistance(0.95 * section * dir), 0);
        EXPECT_GT(c.signedDistance(1.05 * section * dir), 0);
        EXPECT_NEAR(c.signedDistance(1.5 * dir), std::hypot(1.5, 0.4) - 0.7, kOutside);
        EXPECT_NEAR((c.normal(1.2 * section * dir) - dir).norm(), 0, 1e-4);
    }
}

TEST(MpmCollider, CompoundAndGroupShapeAreTheUnionOfTheirParts) {
    // An L of two boxes, once as a btCompoundShape of btBoxShapes (margin 0 so the parts are
    // sharp) and once as a GroupShape of two box primitives (margin 0), both placed at
    // (1, 2, 0) and turned by 15°.
    // Part A: centre (0, 0), half (1, 0.2); part B: centre (0.8, 0.6), half (0.2, 0.4).
    const Vec2 ca(0, 0), ha(1, 0.2), cb(0.8, 0.6), hb(0.2, 0.4);
    btBoxShape a(btVector3(1, 0.2f, 0.5f)), b(btVector3(0.2f, 0.4f, 0.5f));
    a.setMargin(0);
    b.setMargin(0);
    btCompoundShape compound;
    compound.addChildShape(pose(ca.x(), ca.y(), 0), &a);
    compound.addChildShape(pose(cb.x(), cb.y(), 0), &b);
    GroupShape group({test::boxPrimitive({ca.x(), ca.y(), 0}, {ha.x(), ha.y(), 0.5}),
                      test::boxPrimitive({cb.x(), cb.y(), 0}, {hb.x(), hb.y(), 0.5})},
                     0.0);
    const double angle = 15 * std::numbers::pi / 180;
    const Vec2 origin(1, 2);
    const Eigen::Rotation2Dd toLocal(-angle);
    for (btCollisionShape* shape : {static_cast<btCollisionShape*>(&compound), static_cast<btCollisionShape*>(&group)}) {
        btCollisionObject o = objectWith(*shape, pose(origin.x(), origin.y(), 0, angle));
        MpmCollider c(o);
        EXPECT_EQ(c.pieceCount(), 2);
        for (const Vec2& p : lattice(-0.5, 3.5, 32)) {
            const Vec2 q = toLocal * (p - origin);
            const double da = boxDistance(q - ca, ha), db = boxDistance(q - cb, hb);
            const double exact = std::min(da, db);
            EXPECT_NEAR(c.signedDistance(p), exact, exact < 0 ? kInside : kOutside) << shape->getName() << " " << p.transpose();
        }
        // Above the middle of A's top face, outside: normal straight up in the body frame.
        const Vec2 above = origin + Eigen::Rotation2Dd(angle) * Vec2(-0.5, 0.5);
        EXPECT_NEAR((c.normal(above) - Eigen::Rotation2Dd(angle) * Vec2(0, 1)).norm(), 0, 1e-4);
    }
}

TEST(MpmCollider, VelocityOfASpinningBody) {
    // A dynamic box spinning about z at 2 rad/s while moving at (1, 0.5): the surface velocity
    // is v + ω × r. An extra spin about x adds only an out-of-plane (z) velocity at z = 0
    // points, which the plane drops.
    btBoxShape box(btVector3(0.5f, 0.5f, 0.5f));
    btVector3 inertia;
    box.calculateLocalInertia(1, inertia);
    btRigidBody body(1, nullptr, &box, inertia);
    body.setWorldTransform(pose(1, 2, 0));
    body.setLinearVelocity(btVector3(1, 0.5f, 0));
    body.setAngularVelocity(btVector3(0.3f, 0, 2));
    MpmCollider c(body);
    for (const Vec2& p : lattice(0, 3, 6)) {
        const Vec2 r = p - Vec2(1, 2);
        const Vec2 expected = Vec2(1, 0.5) + 2 * Vec2(-r.y(), r.x());
        EXPECT_NEAR((c.velocity(p) - expected).norm(), 0, 1e-5) << p.transpose();
    }
}

TEST(MpmCollider, UpdateFollowsTheBodyThroughTheWorldStep) {
    test::TestWorld w;
    w.world.setGravity(btVector3(0, 0, 0));
    btBoxShape box(btVector3(0.5f, 0.5f, 0.5f));
    btVector3 inertia;
    box.calculateLocalInertia(1, inertia);
    btRigidBody body(1, nullptr, &box, inertia);
    body.setWorldTransform(pose(0, 0, 0));
    body.setLinearVelocity(btVector3(0, 1, 0));
    w.world.addRigidBody(&body);
    MpmCollider c(body);
    EXPECT_NEAR(c.signedDistance(Vec2(0, 1)), 0.5, kOutside);
    w.step(60); // 0.25 s at 1 m/s
    EXPECT_NEAR(c.signedDistance(Vec2(0, 1)), 0.5, kOutside); // the snapshot has not moved
    c.update();
    EXPECT_NEAR(c.signedDistance(Vec2(0, 1)), 0.25, 1e-4);
    EXPECT_NEAR((c.velocity(Vec2(0, 1)) - Vec2(0, 1)).norm(), 0, 1e-5);
    w.world.removeRigidBody(&body);
}

std::string messageOf(const std::function<void()>& f) {
    try {
        f();
    } catch (const InputError& e) {
        return e.what();
    }
    return "(no InputError)";
}

TEST(MpmCollider, BadInputIsNamed) {
    // A triangle mesh has no inside: rejected, naming its type, also inside a compound.
    btTriangleMesh triangles;
    triangles.addTriangle(btVector3(0, 0, 0), btVector3(1, 0, 0), btVector3(0, 0, 1));
    btBvhTriangleMeshShape mesh(&triangles, true);
    btCollisionObject meshObject = objectWith(mesh, btTransform::getIdentity());
    std::string m = messageOf([&] { MpmCollider c(meshObject); });
    EXPECT_NE(m.find("BVHTRIANGLEMESH"), std::string::npos) << m;
    btCompoundShape compound;
    btSphereShape sphere(1);
    compound.addChildShape(btTransform::getIdentity(), &sphere);
    compound.addChildShape(btTransform::getIdentity(), &mesh);
    btCollisionObject compoundObject = objectWith(compound, btTransform::getIdentity());
    m = messageOf([&] { MpmCollider c(compoundObject); });
    EXPECT_NE(m.find("child 1"), std::string::npos) << m;
    EXPECT_NE(m.find("BVHTRIANGLEMESH"), std::string::npos) << m;

    // Non-finite poses, of the object or of the plane, and a bent plane basis.
    btCollisionObject nanObject = objectWith(sphere, pose(std::nan(""), 0, 0));
    m = messageOf([&] { MpmCollider c(nanObject); });
    EXPECT_NE(m.find("world transform is not finite"), std::string::npos) << m;
    btCollisionObject good = objectWith(sphere, btTransform::getIdentity());
    m = messageOf([&] { MpmCollider c(good, pose(0, std::numeric_limits<double>::infinity(), 0)); });
    EXPECT_NE(m.find("simulation plane transform is not finite"), std::string::npos) << m;
    btTransform squashed = btTransform::getIdentity();
    squashed.getBasis()[1][1] = 0.5f;
    m = messageOf([&] { MpmCollider c(good, squashed); });
    EXPECT_NE(m.find("not orthonormal"), std::string::npos) << m;

    // A plane shape parallel to the simulation plane has no edge in it.
    btStaticPlaneShape floor(btVector3(0, 0, 1), 0);
    btCollisionObject floorObject = objectWith(floor, btTransform::getIdentity());
    m = messageOf([&] { MpmCollider c(floorObject); });
    EXPECT_NE(m.find("parallel to the simulation plane"), std::string::npos) << m;

    // update() on a body that went non-finite throws and keeps the last good snapshot.
    MpmCollider c(good);
    good.getWorldTransform().setOrigin(btVector3(std::nanf(""), 0, 0));
    EXPECT_THROW(c.update(), InputError);
    EXPECT_NEAR(c.signedDistance(Vec2(2, 0)), 1, kOutside);
}

// ---- MPM material on Bullet bodies -------------------------------------------------------

// A disc of soft elastic material (E 0.2 MPa, ρ 1000: wave speed ~15 m/s), dx = 5 cm.
mpm::Scene discScene(Vec2 centre, double radius) {
    mpm::Scene s;
    s.grid.dx = 0.05;
    s.grid.ppc = 2;
    s.gravity = Vec2(0, -9.81);
    mpm::Material m;
    m.name = "rubber";
    m.model = mpm::ConstitutiveModelType::Corotated;
    m.E = 2e5;
    m.nu = 0.3;
    m.rho = 1000;
    s.materials.push_back(m);
    s.bodies.push_back(mpm::Body{mpm::Shape(mpm::CircleShape{centre, radius}), 0, Vec2::Zero()});
    return s;
}

double lowestParticle(const mpm::Solver2D& solver) {
    double y = std::numeric_limits<double>::infinity();
    for (const Vec2& x : solver.particles().x) y = std::min(y, x.y());
    return y;
}

// kThreads: the MPM solvers here run on one thread. CTest runs two test programs at once on
// this 2-core machine, and OpenMP teams of two would wait at every barrier for a descheduled
// thread (the same reason as tests/mpm/single_thread_environment.cpp).

// The top face of the box the disc lands on: 0.3 cells above the grid line y = 0.5, so that
// no grid node lies on the face, where float rounding of the Bullet distance (±1e-7 m)
// would decide the node's side differently from the analytic box.
constexpr double kTop = 0.515;

struct DropResult {
    double restCentreY = 0, restLowest = 0, restSpeed = 0, lowestEver = 0, energyGain = 0, dropEnergy = 0;
    double impactSpeed = 0;
    double seconds = 0;
};

// Drops a disc of radius 0.3 m, its bottom 0.2 m above the top face, onto `collider` for
// `duration` seconds with grid damping `damping` (1/s).
DropResult drop(std::shared_ptr<const mpm::Collider> collider, double damping, double duration) {
    const auto clockStart = std::chrono::steady_clock::now();
    const double radius = 0.3, height = 0.2;
    mpm::Scene s = discScene(Vec2(0, kTop + height + radius), radius);
    s.damping = damping;
    mpm::Solver2D solver(s);
    solver.setThreads(1); // see kThreads
    solver.addCollider(std::move(collider));
    DropResult r;
    const mpm::Totals start = mpm::totals(solver);
    r.dropEnergy = start.mass * 9.81 * height;
    r.impactSpeed = std::sqrt(2 * 9.81 * height);
    r.lowestEver = lowestParticle(solver);
    double highest = start.total();
    for (int frame = 0; frame < int(std::lround(duration / 0.02)); ++frame) {
        solver.advance(0.02);
        highest = std::max(highest, mpm::totals(solver).total());
        r.lowestEver = std::min(r.lowestEver, lowestParticle(solver));
    }
    const mpm::Totals end = mpm::totals(solver);
    r.energyGain = highest - start.total();
    r.restCentreY = end.centreOfMass.y();
    r.restLowest = lowestParticle(solver);
    r.restSpeed = end.momentum.norm() / end.mass;
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - clockStart).count();
    return r;
}

// Bullet static box, top face at y = kTop (half extents 1 × 0.25 × 0.5), default margin.
struct BulletBox {
    btBoxShape shape{btVector3(1, 0.25f, 0.5f)};
    btRigidBody body{0, nullptr, &shape};
    BulletBox() { body.setWorldTransform(pose(0, kTop - 0.25, 0)); }
};

std::shared_ptr<const mpm::Collider> analyticBox() {
    return std::make_shared<mpm::BoxCollider>(mpm::Box{Vec2(-1, kTop - 0.5), Vec2(1, kTop)});
}

TEST(MpmColliderMpm, DiscDropGainsNoEnergyAndDoesNotPenetrate) {
    // Undamped impact and rebound (0.6 s: the fall takes 0.2 s). Kinetic + elastic +
    // gravitational energy may only fall (grid collisions remove the normal velocity);
    // 2e-3 of the drop energy allows for the explicit step's discrete energy.
    BulletBox box;
    const DropResult r = drop(std::make_shared<MpmCollider>(box.body), 0.0, 0.6);
    std::printf("undamped drop: %.2f s wall clock, lowest particle ever %.4f m\n", r.seconds, r.lowestEver);
    EXPECT_LT(r.energyGain, 2e-3 * r.dropEnergy);
    // No penetration: the grid stops material at the face; particles, which sit half a
    // spacing (a quarter cell) above it at rest, sink to the face at most during impact.
    EXPECT_GT(r.lowestEver, kTop - 0.1 * 0.05);
}

TEST(MpmColliderMpm, DiscComesToRestOnABulletBoxLikeOnTheAnalyticBox) {
    // Damped (4/s) so that the rebound dies out within 1.5 s.
    BulletBox box;
    const DropResult bullet = drop(std::make_shared<MpmCollider>(box.body), 4.0, 1.5);
    const DropResult analytic = drop(analyticBox(), 4.0, 1.5);
    std::printf("damped drop: Bullet box %.2f s, analytic box %.2f s wall clock\n", bullet.seconds, analytic.seconds);
    std::printf("rest: centre %.5f / %.5f m, lowest %.5f / %.5f m, speed %.2e m/s\n", bullet.restCentreY,
                analytic.restCentreY, bullet.restLowest, analytic.restLowest, bullet.restSpeed);
    const double dx = 0.05;
    // At rest on the top face: the centre of mass a radius above it (less a static sag of
    // ρgR/E ≈ 1.5% strain, under a centimetre) within half a cell.
    EXPECT_NEAR(bullet.restCentreY, kTop + 0.3, 0.5 * dx);
    // The lowest particle rests above the face by less than a cell, never below it.
    EXPECT_GT(bullet.restLowest, kTop);
    EXPECT_LT(bullet.restLowest, kTop + dx);
    // At rest: the mean speed below 2% of the impact speed (1.98 m/s).
    EXPECT_LT(bullet.restSpeed, 0.02 * bullet.impactSpeed);
    // The Bullet box and the solver's own analytic box give the same motion: their distances
    // differ by float rounding only (the box's rounded edges are far from the disc).
    EXPECT_NEAR(bullet.restCentreY, analytic.restCentreY, 1e-4);
    EXPECT_NEAR(bullet.restLowest, analytic.restLowest, 1e-4);
}

TEST(MpmColliderMpm, MovingBulletBodyCarriesTheMaterial) {
    // A Bullet box (no gravity in the Bullet world) rising at 0.5 m/s under a block of MPM
    // material resting on it, with the MPM gravity pulling the block down. With update()
    // after every Bullet step, the block rides on the box: between 0.2 s and 0.6 s its centre
    // of mass rises at the box's speed within 2%, and its lowest particle stays within half
    // a cell of the moving top face at every step.
    test::TestWorld w;
    w.world.setGravity(btVector3(0, 0, 0));
    btBoxShape boxShape(btVector3(1, 0.25f, 0.5f));
    btVector3 inertia;
    boxShape.calculateLocalInertia(1000, inertia);
    btRigidBody box(1000, nullptr, &boxShape, inertia);
    box.setWorldTransform(pose(0, kTop - 0.25, 0));
    box.setLinearVelocity(btVector3(0, 0.5f, 0));
    box.setActivationState(DISABLE_DEACTIVATION);
    w.world.addRigidBody(&box);
    auto collider = std::make_shared<MpmCollider>(box);

    mpm::Scene s = discScene(Vec2::Zero(), 0.1);
    s.bodies[0].shape = mpm::Shape(mpm::RectShape{Vec2(-0.3, kTop), Vec2(0.3, kTop + 0.3)});
    mpm::Solver2D solver(s);
    solver.setThreads(1); // see kThreads
    solver.addCollider(collider);
    const double frame = 1.0 / 240;
    double y0 = 0, worstGap = 0;
    for (int k = 1; k <= 144; ++k) { // 0.6 s
        w.world.stepSimulation(btScalar(frame), 1, btScalar(frame));
        collider->update();
        solver.advance(frame);
        const double boxTop = double(box.getWorldTransform().getOrigin().y()) + 0.25;
        worstGap = std::max(worstGap, std::abs(lowestParticle(solver) - boxTop));
        if (k == 48) y0 = mpm::totals(solver).centreOfMass.y(); // 0.2 s
    }
    const double boxTop = double(box.getWorldTransform().getOrigin().y()) + 0.25;
    EXPECT_NEAR(boxTop, kTop + 0.5 * 0.6, 1e-3); // Bullet moved the box as set
    const double rise = (mpm::totals(solver).centreOfMass.y() - y0) / 0.4;
    std::printf("moving box: block rises at %.4f m/s, worst gap to the face %.4f m\n", rise, worstGap);
    EXPECT_NEAR(rise, 0.5, 0.02 * 0.5);
    EXPECT_LT(worstGap, 0.5 * s.grid.dx);
    w.world.removeRigidBody(&box);
}

} // namespace
} // namespace shatter
