// Bodies in FractureMode::Subdivide (source 000 §3.6): a hit cuts the primitives near it, the
// body stays the same rigid body, and a plastic body dents on the finer primitives.
#include "tests/bullet_ext/fracture/FractureFixtures.h"
#include "tests/bullet_ext/fracture/PlateHit.h"

#include <shatter/bullet_ext/Plugin.h>
#include <shatter/plugin/common/InputError.h>
#include <shatter/plugin/geometry/PhysicalMeshBuilder.h>

#include <gtest/gtest.h>

namespace shatter {
namespace {

BodySettings subdividing(Deformation deformation) {
    BodySettings s;
    s.deformation = deformation;
    s.fracture.enabled = true;
    s.fracture.mode = FractureMode::Subdivide;
    s.fracture.pattern = PatternKind::Voronoi;
    s.fracture.setCells(48);
    s.fracture.radius = 0.2;
    s.fracture.threshold = 1.0;
    s.fracture.coolDown = 0.0;
    return s;
}

int count(std::vector<Event> events, EventType type) {
    return int(std::count_if(events.begin(), events.end(), [&](const Event& e) { return e.type == type; }));
}

TEST(SubdivisionEvent, TheSameRigidBodyKeepsItsMassAndMomentaWithFinerPrimitives) {
    for (Deformation d : {Deformation::None, Deformation::Plastic}) {
        test::TestWorld w;
        w.world.setGravity(btVector3(0, 0, 0));
        Plugin plugin(w.world);
        VisualBody& body = plugin.addVisualBody(test::plate(4, 4, 0.25), subdividing(d), btTransform::getIdentity());
        btRigidBody* rigid = &body.rigidBody();
        rigid->setLinearVelocity(btVector3(1, 2, 3));
        rigid->setAngularVelocity(btVector3(0.5f, -1, 2));
        const auto before = body.physicalMesh();
        test::BulletMomenta p0;
        p0.add(*rigid);
        const btVector3 corner = body.meshTransform() * btVector3(0.01f, 0, 0.01f); // far from the hit
        const std::vector<Eigen::Vector3d> surface = body.visualMesh().positions;
        plugin.takeEvents();
        EXPECT_TRUE(plugin.fracture(body, body.meshTransform() * btVector3(0.55f, 0, 0.45f), btVector3(0, -1, 0)).empty());
        const auto& after = body.physicalMesh();
        EXPECT_EQ(&body.rigidBody(), rigid);
        EXPECT_GT(after.primitives.size(), before.primitives.size() + 10);
        EXPECT_EQ(count(plugin.takeEvents(), EventType::BodySubdivided), 1);
        EXPECT_LT(std::abs(after.mass.mass - before.mass.mass) / before.mass.mass, 1e-9);
        EXPECT_LT((after.mass.centerOfMass - before.mass.centerOfMass).norm(), 1e-9);
        test::BulletMomenta p1;
        p1.add(*rigid);
        EXPECT_NEAR(p1.mass, p0.mass, 1e-6 * p0.mass);
        EXPECT_LT((p1.linear - p0.linear).norm(), 1e-5 * p0.linear.norm());
        EXPECT_LT((p1.angular - p0.angular).norm(), 1e-5 * p0.angular.norm());
        EXPECT_LT((body.meshTransform() * btVector3(0.01f, 0, 0.01f) - corner).length(), 1e-5);
        EXPECT_EQ(after.componentCount(), 1);
        // The visual surface stays where it was: the old vertices in place (Bullet's float
        // transform), the new ones on the plate's plane.
        const auto& now = body.visualMesh().positions;
        ASSERT_GT(now.size(), surface.size());
        for (size_t i = 0; i < surface.size(); ++i) EXPECT_LT((now[i] - surface[i]).norm(), 1e-5);
        const Eigen::Vector3d normal = toEigen(body.meshTransform().getBasis() * btVector3(0, 1, 0));
        for (size_t i = surface.size(); i < now.size(); ++i) EXPECT_LT(std::abs(normal.dot(now[i] - surface[0])), 1e-5);
        EXPECT_EQ(body.solver() != nullptr, d == Deformation::Plastic);
        EXPECT_EQ(body.solver() ? body.solver()->particles().size() : 0, d == Deformation::Plastic ? int(after.primitives.size()) : 0);
    }
}

// A 2 kg ball dropped at 10 m/s onto a static plastic plate of 4 × 4 tiles of 25 cm, at
// (0.55, 0.45); returns the plate (kept alive by the scene).
struct DroppedBall {
    test::TestWorld w;
    Plugin plugin{w.world};
    test::FallingBall ball;
    VisualBody* body = nullptr;
    std::vector<Event> events;

    explicit DroppedBall(bool subdivide) {
        BodySettings s = subdivide ? subdividing(Deformation::Plastic) : BodySettings{};
        s.deformation = Deformation::Plastic;
        s.dynamic = false;
        s.plastic.threshold = 3.0;
        body = &plugin.addVisualBody(test::plate(4, 4, 0.25), s, btTransform::getIdentity());
        ball.drop(w, 2.0f, 30);
        events = plugin.takeEvents();
    }
    // The visual vertices' largest sink below the plate's surface (y = 0 at rest, new vertices
    // too), and the farthest (in the plate's plane) from the hit of those that sank more than a
    // fifth of it.
    std::pair<double, double> dent() {
        const auto& now = body->visualMesh().positions;
        double deepest = 0.0, reach = 0.0;
        for (const auto& p : now) deepest = std::max(deepest, -p.y());
        for (const auto& p : now)
            if (-p.y() > 0.2 * deepest) reach = std::max(reach, Eigen::Vector2d(p.x() - 0.55, p.z() - 0.45).norm());
        return {deepest, reach};
    }
};

TEST(SubdivisionEvent, AHardHitSubdividesThenDentsFinerThanOnTheCoarsePlate) {
    DroppedBall coarse(false), fine(true);
    EXPECT_EQ(count(coarse.events, EventType::BodySubdivided), 0);
    ASSERT_EQ(count(fine.events, EventType::BodySubdivided), 1);
    // The subdivision comes first, the dent on its pieces in the same step (never coarse first).
    const auto first = std::find_if(fine.events.begin(), fine.events.end(), [](const Event& e) {
        return e.type == EventType::BodySubdivided || e.type == EventType::BodyDented;
    });
    ASSERT_NE(first, fine.events.end());
    EXPECT_EQ(first->type, EventType::BodySubdivided);
    EXPECT_GE(count(fine.events, EventType::BodyDented), 1);
    const auto [coarseDepth, coarseReach] = coarse.dent();
    const auto [fineDepth, fineReach] = fine.dent();
    EXPECT_GT(coarseDepth, 0.01);
    EXPECT_GT(fineDepth, 0.01);
    // The same blow, spread over 3 rings of small pieces instead of 3 rings of 25 cm tiles
    // (measured: 9 cm against 71 cm, the whole plate).
    EXPECT_LT(fineReach, 0.6 * coarseReach) << "fine " << fineReach << " m, coarse " << coarseReach << " m";
    EXPECT_GT(fine.body->physicalMesh().primitives.size(), 3 * coarse.body->physicalMesh().primitives.size());
    EXPECT_NEAR(fine.body->physicalMesh().mass.mass, coarse.body->physicalMesh().mass.mass,
                1e-9 * coarse.body->physicalMesh().mass.mass);
}

TEST(SubdivisionEvent, TheSameHitGivesTheSameBits) {
    DroppedBall a(true), b(true);
    const auto& pa = a.body->physicalMesh().primitives;
    const auto& pb = b.body->physicalMesh().primitives;
    ASSERT_EQ(pa.size(), pb.size());
    for (size_t i = 0; i < pa.size(); ++i) EXPECT_EQ(pa[i].vertices(), pb[i].vertices());
    EXPECT_EQ(a.body->visualMesh().positions, b.body->visualMesh().positions);
}

TEST(SubdivisionEvent, DepthBoundsHowOftenABodySubdivides) {
    test::TestWorld w;
    Plugin plugin(w.world);
    BodySettings s = subdividing(Deformation::None);
    s.fracture.depth = 0; // once
    VisualBody& body = plugin.addVisualBody(test::plate(4, 4, 0.25), s, btTransform::getIdentity());
    plugin.fracture(body, btVector3(0.3f, 0, 0.3f), btVector3(0, -1, 0));
    const size_t once = body.physicalMesh().primitives.size();
    EXPECT_GT(once, 16u);
    plugin.fracture(body, btVector3(0.7f, 0, 0.7f), btVector3(0, -1, 0));
    EXPECT_EQ(body.physicalMesh().primitives.size(), once);
}

TEST(SubdivisionEvent, ASubdivisionThatDoesNotMatchTheBodyIsRejected) {
    test::TestWorld w;
    Plugin plugin(w.world);
    VisualBody& body = plugin.addVisualBody(test::plate(2, 2, 0.25), subdividing(Deformation::Plastic), btTransform::getIdentity());
    const auto mesh = body.physicalMesh();
    w.world.removeRigidBody(&body.rigidBody());
    EXPECT_THROW(body.subdivide(mesh, {0, 1, 2}, 3), InputError);        // 4 primitives, 3 parents
    EXPECT_THROW(body.subdivide(mesh, {0, 1, 2, 9}, 3), InputError);     // no primitive 9
    EXPECT_THROW(body.subdivide(mesh, {1, 0, 2, 3}, 4), InputError);     // kept ones out of order
    EXPECT_THROW(body.subdivide(mesh, {0, 1, 2, 3}, 5), InputError);     // more kept than primitives
    EXPECT_EQ(body.physicalMesh().primitives.size(), 4u);
    w.world.addRigidBody(&body.rigidBody());
}

TEST(SubdivisionEvent, ModeAndDeformationMustGoTogether) {
    test::TestWorld w;
    Plugin plugin(w.world);
    auto rejects = [&](const BodySettings& s, const std::string& words) {
        try {
            plugin.addVisualBody(test::plate(2, 2, 0.25), s, btTransform::getIdentity());
            ADD_FAILURE() << words << " was accepted";
        } catch (const InputError& e) {
            EXPECT_NE(std::string(e.what()).find("body 'plate': " + words), std::string::npos) << e.what();
        }
    };
    rejects(subdividing(Deformation::Soft), "fracture mode Subdivide needs deformation None or Plastic");
    BodySettings shatter = subdividing(Deformation::Plastic);
    shatter.fracture.mode = FractureMode::Shatter;
    rejects(shatter, "fracture needs deformation None");
    BodySettings unknown = subdividing(Deformation::Plastic);
    unknown.fracture.mode = static_cast<FractureMode>(7);
    rejects(unknown, "fracture mode must be Shatter or Subdivide, got 7");
    EXPECT_THROW(fractureModeNamed("subdivid"), InputError);
    EXPECT_EQ(fractureModeNamed("subdivide"), FractureMode::Subdivide);
    EXPECT_TRUE(plugin.bodies().empty());
}

} // namespace
} // namespace shatter
