// The Bullet side: a lattice body in a world, broken by a ball; conservation, determinism,
// speed dependence, crack surfaces, bad input.
#include <shatter/bullet_ext/Convert.h>
#include <shatter/bullet_ext/ContactSnapshot.h>
#include <shatter/bullet_ext/lattice/LatticeBody.h>
#include <shatter/bullet_ext/lattice/LatticeSystem.h>
#include <shatter/bullet_ext/Plugin.h>
#include <shatter/bullet_ext/VisualBody.h>
#include <shatter/plugin/common/InputError.h>
#include <shatter/plugin/lattice/Fragments.h>
#include <shatter/plugin/lattice/TetGenerators.h>
#include "tests/bullet_ext/lattice/WallScene.h"
#include "tests/support/PartsConserve.h"
#include "tests/support/TestWorld.h"

#include <gtest/gtest.h>

#include <set>

namespace shatter {
namespace {

using test::WallScene;

TEST(LatticeBody, RestsOnTheGroundWithoutBreaking) {
    for (const char* material : {"adobe", "glass"}) {
        test::TestWorld w;
        w.addGround();
        Plugin plugin(w.world);
        LatticeSettings s;
        s.material = lattice::materialNamed(material);
        LatticeBody& slab = plugin.addLatticeBody(lattice::tetSlab(0.6, 0.4, 0.04, 0.05, 1), s,
                                                  btTransform(btQuaternion::getIdentity(), btVector3(0, 0.03f, 0)));
        w.step(480); // drop 1 cm, then rest for 2 s
        EXPECT_EQ(slab.brokenLinkCount(), 0) << material;
        EXPECT_EQ(slab.pieceCount(), 1) << material;
        const btRigidBody& body = slab.pieces()[0].body->rigidBody();
        EXPECT_LT(body.getLinearVelocity().length(), 0.01f) << material;
        EXPECT_NEAR(body.getCenterOfMassPosition().y(), 0.02f, 0.003f) << material;
        EXPECT_GT(plugin.lattices().timing().analyses, 0) << material; // the landing was analysed
    }
}

TEST(LatticeBody, BallBreaksAnAnchoredWallAndMassIsConserved) {
    WallScene s(8.0);
    const VisualBody* original = s.wall->pieces()[0].body;
    s.w.step(60);
    const LatticeBody& wall = *s.wall;
    ASSERT_GT(wall.pieceCount(), 5);
    EXPECT_GT(wall.brokenLinkCount(), 10);
    // Every tet is in exactly one piece and the pieces' exact masses add up.
    std::vector<int> seen(wall.tetCount(), 0);
    double bulletMass = 0.0;
    for (const auto& p : wall.pieces()) {
        for (int t : p.lattice.particles) ++seen[t];
        const btRigidBody& b = p.body->rigidBody();
        bulletMass += b.getInvMass() > 0 ? 1.0 / double(b.getInvMass()) : p.mass.mass;
        // Anchored pieces are static, the others dynamic unless frozen at rest.
        EXPECT_EQ(p.lattice.anchored || p.frozen, b.getInvMass() == 0);
    }
    for (int n : seen) EXPECT_EQ(n, 1);
    EXPECT_NEAR(wall.currentMass(), wall.initialMass(), 1e-12 * wall.initialMass());
    EXPECT_NEAR(bulletMass, wall.initialMass(), 1e-6 * wall.initialMass()); // Bullet stores float masses
    std::set<int> created;
    int broken = 0;
    for (const Event& e : s.plugin.takeEvents()) {
        if (e.type == EventType::FragmentCreated) created.insert(e.body);
        if (e.type == EventType::LinksBroken) broken += e.count;
    }
    EXPECT_EQ(broken, wall.brokenLinkCount());
    // Every piece is a fragment announced as created, or the wall's own body that kept the
    // anchored rest (only the tets that left were taken out of it).
    for (const auto& p : wall.pieces()) EXPECT_TRUE(created.count(p.body->id()) || p.body == original);
}

TEST(LatticeBody, FragmentsCarryTheMassAndMomentumOfTheirParent) {
    // A free slab, moving and spinning without gravity, is hit by a ball: every split hands
    // the parent's mass, momentum and angular momentum on to its parts (double precision, as
    // computed: 1e-9), and the parts' Bullet bodies move as computed (float: 1e-6).
    test::TestWorld w;
    w.world.setGravity(btVector3(0, 0, 0));
    Plugin plugin(w.world);
    LatticeSettings s;
    s.material = lattice::glass();
    LatticeBody& slab = plugin.addLatticeBody(lattice::tetSlab(0.5, 0.5, 0.04, 0.05, 1), s, btTransform::getIdentity());
    btRigidBody& body = slab.pieces()[0].body->rigidBody();
    body.setLinearVelocity(btVector3(0.5f, 0.2f, -0.3f));
    body.setAngularVelocity(btVector3(0.3f, 2.0f, -0.4f));
    btSphereShape ballShape(0.08f);
    btVector3 inertia;
    ballShape.calculateLocalInertia(20, inertia);
    btRigidBody ball(20, nullptr, &ballShape, inertia);
    ball.setWorldTransform(btTransform(btQuaternion::getIdentity(), btVector3(0, 0.3f, 0)));
    ball.setLinearVelocity(btVector3(0, -15, 0));
    w.world.addRigidBody(&ball);
    w.step(40);
    w.world.removeRigidBody(&ball);
    const auto records = plugin.lattices().takeSplitRecords();
    ASSERT_FALSE(records.empty());
    for (const auto& r : records) {
        test::expectPartsConserveTheWhole(r.parent, r.parts);
    }
    EXPECT_GT(records.front().parts.size(), 1u);
    EXPECT_GT(slab.pieceCount(), 1);
}

TEST(LatticeBody, ConvexPiecesCollideAsHullsWithExactMassProperties) {
    WallScene s(8.0);
    s.w.step(60);
    const LatticeBody& wall = *s.wall;
    ASSERT_GT(wall.pieceCount(), 5);
    int hulls = 0, groups = 0;
    for (const auto& p : wall.pieces()) {
        const btRigidBody& b = p.body->rigidBody();
        const bool convex = lattice::isConvexPiece(wall.lattice(), p.lattice.particles, wall.settings().convexHullTolerance,
                                                   wall.settings().convexHullMaxTets);
        ASSERT_EQ(bool(p.hull), convex);
        if (p.lattice.particles.size() == 1) {
            EXPECT_TRUE(p.hull); // a single tet is always a hull
        }
        if (!p.hull) {
            EXPECT_EQ(b.getCollisionShape(), &p.body->shape());
            ++groups;
            continue;
        }
        ++hulls;
        EXPECT_EQ(b.getCollisionShape(), p.hull.get());
        EXPECT_EQ(b.getCollisionShape()->getShapeType(), CONVEX_HULL_SHAPE_PROXYTYPE);
        EXPECT_FLOAT_EQ(p.hull->getMargin(), float(wall.settings().rigidBody.collisionMargin)); // not Bullet's 4 cm default
        EXPECT_TRUE(p.hull->getConvexPolyhedron() != nullptr);
        // The hull's points are the piece's tet corners where the body is now.
        const Eigen::Isometry3d meshToWorld = toEigen(p.body->meshTransform());
        const Eigen::Isometry3d bodyToWorld = toEigen(b.getWorldTransform());
        std::vector<Eigen::Vector3d> corners;
        for (int t : p.lattice.particles)
            for (int n : wall.lattice().mesh().tets[t]) corners.push_back(meshToWorld * wall.lattice().mesh().nodes[n]);
        for (int i = 0; i < p.hull->getNumPoints(); ++i) {
            const Eigen::Vector3d point = bodyToWorld * toEigen(p.hull->getUnscaledPoints()[i]);
            double nearest = INFINITY;
            for (const auto& c : corners) nearest = std::min(nearest, (c - point).norm());
            EXPECT_LT(nearest, 1e-5);
        }
        // Mass and inertia are the tets' exact ones (principal moments; Bullet holds floats).
        if (b.getInvMass() > 0) {
            EXPECT_NEAR(1.0 / double(b.getInvMass()), p.mass.mass, 1e-6 * p.mass.mass);
            const Eigen::Vector3d moments = p.mass.principal().moments;
            for (int k = 0; k < 3; ++k)
                EXPECT_NEAR(1.0 / double(b.getInvInertiaDiagLocal()[k]), moments[k], 1e-5 * moments.maxCoeff());
            EXPECT_LT((toEigen(b.getCenterOfMassPosition()) - meshToWorld * p.mass.centerOfMass).norm(), 1e-5);
        }
    }
    EXPECT_GT(hulls, 0);
    EXPECT_GT(groups, 0); // the anchored rest of the wall at least
}

TEST(LatticeBody, AFragmentHullsBoxIsTheBoxOfItsTurnedPoints) {
    // Bullet's hull box turns the body-frame box with the body (up to √3 times too wide per
    // axis), and the world grows every box by the global contact breaking threshold; in a heap
    // every box pair is a narrowphase pair, so the box the world sees for a fragment hull is
    // its turned points' exact box grown by its margin and its own (small) breaking threshold.
    WallScene s(8.0);
    s.w.step(60);
    int hulls = 0;
    for (const auto& p : s.wall->pieces()) {
        if (!p.hull) continue;
        ++hulls;
        const btTransform t(btQuaternion(btVector3(1, 2, 3).normalized(), 0.7f), btVector3(0.3f, -1, 2));
        btVector3 lo, hi;
        p.hull->getAabb(t, lo, hi);
        btVector3 exactLo(INFINITY, INFINITY, INFINITY), exactHi = -exactLo;
        for (int i = 0; i < p.hull->getNumPoints(); ++i) {
            exactLo.setMin(t * p.hull->getUnscaledPoints()[i]);
            exactHi.setMax(t * p.hull->getUnscaledPoints()[i]);
        }
        // What btCollisionWorld::updateSingleAabb does with the shape's box.
        lo -= btVector3(gContactBreakingThreshold, gContactBreakingThreshold, gContactBreakingThreshold);
        hi += btVector3(gContactBreakingThreshold, gContactBreakingThreshold, gContactBreakingThreshold);
        const btScalar grow = p.hull->getMargin() + p.hull->getContactBreakingThreshold(gContactBreakingThreshold);
        EXPECT_LT(p.hull->getContactBreakingThreshold(gContactBreakingThreshold), 0.005f); // a few mm for a 10 cm tet
        for (int k = 0; k < 3; ++k) {
            EXPECT_NEAR(lo[k], exactLo[k] - grow, 1e-6f);
            EXPECT_NEAR(hi[k], exactHi[k] + grow, 1e-6f);
        }
        btVector3 looseLo, looseHi; // Bullet's own box, grown by the world
        p.hull->btConvexHullShape::getAabb(t, looseLo, looseHi);
        EXPECT_LE((hi - lo).length(), (looseHi - looseLo).length() + 2 * std::sqrt(3.0f) * gContactBreakingThreshold);
    }
    EXPECT_GT(hulls, 0);
}

TEST(LatticeBody, AConvexPieceAtRestSleepsAfterSleepAfter) {
    // A 10 cm cube of six tets (convex: one hull) set on the ground. Bullet alone lets a body
    // sleep after 2 s at rest; the piece is ready after LatticeSettings::sleepAfter.
    for (double after : {0.25, 100.0}) {
        test::TestWorld w;
        w.addGround();
        Plugin plugin(w.world);
        LatticeSettings s;
        s.rest.sleepAfter = after;
        LatticeBody& cube = plugin.addLatticeBody(lattice::tetBox({0.1, 0.1, 0.1}, {1, 1, 1}), s,
                                                  btTransform(btQuaternion::getIdentity(), btVector3(0, 0.0505f, 0)));
        ASSERT_EQ(cube.pieceCount(), 1);
        ASSERT_TRUE(cube.pieces()[0].hull);
        w.step(240); // 1 s
        const btRigidBody& body = cube.pieces()[0].body->rigidBody();
        if (after < 1.0) {
            EXPECT_EQ(body.getActivationState(), ISLAND_SLEEPING) << after;
        } else {
            EXPECT_NE(body.getActivationState(), ISLAND_SLEEPING) << after;
        }
        EXPECT_NEAR(body.getCenterOfMassPosition().y(), 0.05f, 0.002f);
    }
}

TEST(LatticeBody, ASleepingPieceGivesNoContactImpulses) {
    // The contact snapshot copies the impulses Bullet's solver left in the manifolds; a pair
    // of two bodies that are asleep (or static) is not solved, and its points keep the
    // impulses of the step it fell asleep in, which must not load the lattice again every
    // step: such a pair is marked unsolved.
    test::TestWorld w;
    w.addGround();
    Plugin plugin(w.world);
    LatticeSettings s;
    s.rest.sleepAfter = 0.25;
    s.rest.freezeAtRest = false; // frozen, it would leave the ground's pair and its manifold
    LatticeBody& cube = plugin.addLatticeBody(lattice::tetBox({0.1, 0.1, 0.1}, {1, 1, 1}), s,
                                              btTransform(btQuaternion::getIdentity(), btVector3(0, 0.0505f, 0)));
    const btRigidBody& body = cube.pieces()[0].body->rigidBody();
    // The cube's pair with the ground: whether it is solved, and the impulse its points hold.
    auto groundPair = [&] {
        ContactSnapshot snapshot;
        snapshot.capture(w.dispatcher);
        const auto pairs = snapshot.pairsOf(&body);
        EXPECT_EQ(pairs.size(), 1u);
        const ContactPair& pair = snapshot.pairs()[pairs[0]];
        double held = 0;
        for (const ContactPoint& p : snapshot.points(pair)) held += double(p.impulseOnA.length());
        return std::make_pair(pair.solved, held);
    };
    w.step(30);
    ASSERT_NE(body.getActivationState(), ISLAND_SLEEPING);
    const auto [awakeSolved, awakeHeld] = groundPair();
    EXPECT_TRUE(awakeSolved); // awake: the ground holds it up
    EXPECT_GT(awakeHeld, 0.0);
    w.step(210);
    ASSERT_EQ(body.getActivationState(), ISLAND_SLEEPING);
    const auto [asleepSolved, asleepHeld] = groundPair();
    EXPECT_GT(asleepHeld, 0.0); // Bullet keeps them
    EXPECT_FALSE(asleepSolved);
}

TEST(LatticeBody, LooseFragmentsAreSlowWhenTheirRimIsSlow) {
    // Bullet's angular sleeping threshold (1 rad/s) is for bodies of about a metre; a loose
    // piece's is its linear threshold over its bounding radius (never below Bullet's), so a
    // tet nudged to 2 rad/s in a heap does not restart the heap's deactivation timer.
    WallScene s(8.0);
    s.w.step(60);
    ASSERT_GT(s.wall->pieceCount(), 5);
    const btRigidBody defaults(0, nullptr, nullptr);
    for (const auto& p : s.wall->pieces()) {
        const btRigidBody& b = p.body->rigidBody();
        EXPECT_FLOAT_EQ(b.getLinearSleepingThreshold(), defaults.getLinearSleepingThreshold());
        if (p.lattice.anchored) {
            EXPECT_FLOAT_EQ(b.getAngularSleepingThreshold(), defaults.getAngularSleepingThreshold());
            continue;
        }
        btVector3 centre;
        btScalar radius;
        b.getCollisionShape()->getBoundingSphere(centre, radius);
        const btScalar expected =
            btMax(defaults.getAngularSleepingThreshold(), defaults.getLinearSleepingThreshold() / radius);
        EXPECT_FLOAT_EQ(b.getAngularSleepingThreshold(), expected);
        if (p.lattice.particles.size() == 1) {
            EXPECT_GT(b.getAngularSleepingThreshold(), 2.0f); // a tet of ~10 cm
        }
    }
}

TEST(LatticeBody, SplitPartsStartWithTheComputedVelocities) {
    WallScene s(10.0);
    for (int i = 0; i < 60; ++i) {
        s.w.step(1);
        const auto records = s.plugin.lattices().takeSplitRecords();
        if (records.empty()) continue;
        for (const auto& r : records)
            for (size_t k = 0; k < r.parts.size(); ++k) {
                const btRigidBody& b = r.bodies[k]->rigidBody();
                if (b.getInvMass() == 0) continue;
                const double scale = std::max(1.0, r.parts[k].velocity.norm());
                // Set after the step's integration, so they are what Bullet holds now.
                EXPECT_LT((toEigen(b.getLinearVelocity()) - r.parts[k].velocity).norm(), 1e-6 * scale);
                EXPECT_LT((toEigen(b.getAngularVelocity()) - r.parts[k].angularVelocity).norm(), 1e-6 * scale);
                EXPECT_LT((toEigen(b.getCenterOfMassPosition()) - r.parts[k].centre).norm(), 1e-5);
            }
        return;
    }
    FAIL() << "the wall never broke";
}

std::vector<std::vector<int>> fragments(const LatticeBody& body) {
    std::vector<std::vector<int>> out;
    for (const auto& p : body.pieces()) out.push_back(p.lattice.particles);
    return out;
}

TEST(LatticeBody, SameSeedGivesIdenticalFragments) {
    WallScene a(8.0, 5), b(8.0, 5);
    a.w.step(60);
    b.w.step(60);
    EXPECT_EQ(fragments(*a.wall), fragments(*b.wall));
    ASSERT_EQ(a.wall->pieceCount(), b.wall->pieceCount());
    for (int i = 0; i < a.wall->pieceCount(); ++i) {
        const btTransform& ta = a.wall->pieces()[i].body->rigidBody().getWorldTransform();
        const btTransform& tb = b.wall->pieces()[i].body->rigidBody().getWorldTransform();
        EXPECT_TRUE(ta.getOrigin() == tb.getOrigin() && ta.getBasis() == tb.getBasis()) << "piece " << i;
    }
    WallScene c(8.0, 6);
    c.w.step(60);
    EXPECT_NE(fragments(*a.wall), fragments(*c.wall)); // another seed, another mesh jitter and cracks
}

TEST(LatticeBody, FragmentCountGrowsWithImpactSpeed) {
    std::vector<int> counts;
    for (double speed : {2.0, 6.0, 18.0}) {
        WallScene s(speed);
        s.w.step(60);
        counts.push_back(s.wall->pieceCount());
    }
    EXPECT_LE(counts[0], counts[1]);
    EXPECT_LE(counts[1], counts[2]);
    EXPECT_LT(counts[0], counts[2]);
}

TEST(LatticeBody, FragmentSurfacesIncludeTheCrackFaces) {
    WallScene s(8.0);
    s.w.step(60);
    const LatticeBody& wall = *s.wall;
    ASSERT_GT(wall.pieceCount(), 1);
    // Faces between tets of different pieces are drawn once from each side.
    std::vector<int> pieceOf(wall.tetCount());
    for (int i = 0; i < wall.pieceCount(); ++i)
        for (int t : wall.pieces()[i].lattice.particles) pieceOf[t] = i;
    int cracks = 0;
    for (const auto& l : wall.lattice().links()) cracks += pieceOf[l.a] != pieceOf[l.b];
    size_t faces = 0;
    for (const auto& p : wall.pieces()) faces += p.body->physicalMesh().visual.faces.size();
    EXPECT_EQ(int(faces), wall.lattice().faces().boundaryCount + 2 * cracks);
}

TEST(LatticeBody, BadInputIsAnErrorNamingTheBody) {
    test::TestWorld w;
    Plugin plugin(w.world);
    const lattice::TetMesh box = lattice::tetBox({1, 1, 1}, {2, 2, 2});
    LatticeSettings s;
    s.name = "crate";
    auto message = [&](const LatticeSettings& settings, const btTransform& pose) -> std::string {
        try {
            plugin.addLatticeBody(box, settings, pose);
        } catch (const InputError& e) {
            return e.what();
        }
        return "";
    };
    btTransform nan = btTransform::getIdentity();
    nan.setOrigin(btVector3(0, NAN, 0));
    EXPECT_NE(message(s, nan).find("body 'crate': pose has a non-finite value"), std::string::npos);
    LatticeSettings bad = s;
    bad.material.density = 0;
    EXPECT_NE(message(bad, btTransform::getIdentity()).find("body 'crate': material 'adobe' density must be positive"),
              std::string::npos);
    bad = s;
    bad.material.strength = -5;
    EXPECT_NE(message(bad, btTransform::getIdentity()).find("strength must be positive"), std::string::npos);
    bad = s;
    bad.fixedTets = {48};
    EXPECT_NE(message(bad, btTransform::getIdentity()).find("body 'crate': fixed tet index must be in [0, 48)"), std::string::npos);
    bad = s;
    bad.cleavingPlanes.push_back({Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), 0.0, 0.5});
    EXPECT_NE(message(bad, btTransform::getIdentity()).find("body 'crate': cleaving plane 0 normal must be finite and non-zero"), std::string::npos);
    bad = s;
    bad.rest.wakeSpeed = NAN;
    EXPECT_NE(message(bad, btTransform::getIdentity()).find("body 'crate': wake speed (m/s) must be >= 0 and finite, got nan"), std::string::npos);
    bad = s;
    bad.rest.wakeDrift = -0.01;
    EXPECT_NE(message(bad, btTransform::getIdentity()).find("body 'crate': wake drift (m) must be >= 0 and finite, got -0.01"), std::string::npos);
    bad = s;
    bad.rest.wakeMassRatio = -0.02;
    EXPECT_NE(message(bad, btTransform::getIdentity()).find("body 'crate': wake mass ratio must be >= 0 and finite, got -0.02"), std::string::npos);
    bad = s;
    bad.minFragmentSize = -0.05;
    EXPECT_NE(message(bad, btTransform::getIdentity()).find("body 'crate': min fragment size (m) must be >= 0 and finite, got -0.05"), std::string::npos);
    bad.minFragmentSize = INFINITY;
    EXPECT_NE(message(bad, btTransform::getIdentity()).find("min fragment size (m) must be >= 0 and finite, got inf"), std::string::npos);
    EXPECT_TRUE(plugin.bodies().empty()); // nothing half-added
}

} // namespace
} // namespace shatter
