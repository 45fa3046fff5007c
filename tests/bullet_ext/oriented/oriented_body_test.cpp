// Deformable Shatter bodies in a Bullet world (source 000 §3.2-3.5): plastic dents from
// contact speeds, soft bodies colliding through Bullet, and what the app sees of both.
#include <shatter/bullet_ext/Plugin.h>
#include "tests/bullet_ext/oriented/CubeBlock.h"
#include "tests/support/TestWorld.h"

#include <gtest/gtest.h>

namespace shatter {
namespace {

// An open nx × nz quad sheet of cell h at height y, facing +y (extruded downwards).
geometry::PhysicalMesh sheet(int nx, int nz, double h, double y, double thickness) {
    std::vector<Eigen::Vector3d> positions;
    for (int j = 0; j <= nz; ++j)
        for (int i = 0; i <= nx; ++i) positions.push_back({i * h, y, j * h});
    std::vector<std::vector<int>> faces;
    auto v = [&](int i, int j) { return j * (nx + 1) + i; };
    for (int j = 0; j < nz; ++j)
        for (int i = 0; i < nx; ++i) faces.push_back({v(i, j), v(i, j + 1), v(i + 1, j + 1), v(i + 1, j)});
    geometry::PhysicalMeshSettings s;
    s.thickness = thickness;
    s.density = 7800; // steel
    return geometry::buildPhysicalMesh("sheet", positions, faces, s);
}


// Drops a 2 kg ball at `speed` straight down onto a static plastic 1 m steel sheet and
// returns the sheet's deepest dent (m).
double dentDepth(double speed) {
    test::TestWorld w;
    Plugin plugin(w.world);
    BodySettings settings;
    settings.dynamic = false;
    settings.deformation = Deformation::Plastic;
    settings.plastic.threshold = 3.0;
    VisualBody& plate = plugin.addVisualBody(sheet(10, 10, 0.1, 0.0, 0.01), settings, btTransform::getIdentity());
    btSphereShape ballShape(0.1f);
    btVector3 inertia;
    ballShape.calculateLocalInertia(2.0f, inertia);
    btRigidBody ball(2.0f, nullptr, &ballShape, inertia);
    ball.setWorldTransform(btTransform(btQuaternion::getIdentity(), btVector3(0.55f, 0.12f, 0.55f)));
    ball.setLinearVelocity(btVector3(0, btScalar(-speed), 0));
    w.world.addRigidBody(&ball);
    w.step(60);
    w.world.removeRigidBody(&ball);
    EXPECT_LE(plate.plasticEvents(), 3); // one impact, not a dent per step of resting contact
    return plate.dentDepthMax();
}

TEST(PlasticBody, DentsOnlyAboveTheThresholdAndDeeperForFasterImpacts) {
    EXPECT_EQ(dentDepth(2.0), 0.0); // below the 3 m/s threshold: rigid and unchanged
    const double medium = dentDepth(6.0), fast = dentDepth(12.0);
    // The source's offset is speed × step: 6/240 = 25 mm and 12/240 = 50 mm at the hit tile.
    EXPECT_GT(medium, 0.01);
    EXPECT_GT(fast, 1.5 * medium);
    EXPECT_LT(fast, 0.06);
}

TEST(PlasticBody, DentKeepsMassAndTheVelocityOfEveryPoint) {
    test::TestWorld w;
    Plugin plugin(w.world);
    BodySettings settings;
    settings.deformation = Deformation::Plastic;
    VisualBody& body = plugin.addVisualBody(sheet(6, 6, 0.1, 0.0, 0.01), settings, btTransform::getIdentity());
    btRigidBody& rigid = body.rigidBody();
    rigid.setLinearVelocity(btVector3(1, 2, 3));
    rigid.setAngularVelocity(btVector3(0.5f, -1, 2));
    const double massBefore = 1.0 / double(rigid.getInvMass());
    const btVector3 probe = body.meshTransform() * btVector3(0.05f, 0, 0.05f); // an undented corner tile
    const btVector3 velocityBefore = rigid.getVelocityInLocalPoint(probe - rigid.getCenterOfMassPosition());
    w.world.removeRigidBody(&rigid);
    const oriented::Dent dent{14, Eigen::Vector3d(0, -0.03, 0)};
    body.dent(std::span(&dent, 1));
    w.world.addRigidBody(&rigid);
    EXPECT_NEAR(1.0 / double(rigid.getInvMass()), massBefore, 1e-9 * massBefore);
    // The undented corner is where it was and moves as it did (float Bullet: 1e-5).
    EXPECT_LT((body.meshTransform() * btVector3(0.05f, 0, 0.05f) - probe).length(), 1e-5);
    const btVector3 velocityAfter = rigid.getVelocityInLocalPoint(probe - rigid.getCenterOfMassPosition());
    EXPECT_LT((velocityAfter - velocityBefore).length(), 1e-5);
    EXPECT_NEAR(body.dentDepthMax(), 0.03, 1e-9);
}

TEST(SoftBody, DroppedJellyComesToRestInItsRestShape) {
    test::TestWorld w;
    w.addGround(0.8);
    Plugin plugin(w.world);
    BodySettings settings;
    settings.deformation = Deformation::Soft;
    settings.rigidBody.friction = 0.8;
    settings.solver.stiffness = 0.3;
    const auto mesh = test::cubes(3, 0.05, 0.0, 0.05);
    ASSERT_EQ(mesh.primitives.size(), 27u);
    ASSERT_EQ(mesh.componentCount(), 1);
    VisualBody& jelly = plugin.addVisualBody(mesh, settings, btTransform::getIdentity());
    w.step(720); // 3 s
    const auto& p = jelly.solver()->particles();
    double lowest = 1e9;
    for (const auto& x : p.position) lowest = std::min(lowest, x.y());
    EXPECT_LT(p.kineticEnergy(), 1e-8);   // at rest
    EXPECT_LT(p.restShapeError(), 1e-3); // in its rest shape within 1 mm (it sags a little)
    EXPECT_NEAR(lowest, 0.025, 2e-3);     // bottom cubes' centres half a cube above the ground
    // The visual mesh is welded from the deformed primitives: finite and near the particles.
    const auto& visual = jelly.visualMesh();
    for (const auto& v : visual.positions) {
        ASSERT_TRUE(v.allFinite());
        EXPECT_GT(v.y(), -2e-3);
    }
}

TEST(SoftBody, DisconnectedPartsAreSimulatedApartWithAWarning) {
    // 2 × 2 × 2 cubes with 2 cm gaps: eight parts, each its own shape-matching group, each
    // falling on its own. (The upper parts land on the lower ones through self-contact:
    // soft_coupling_test.cpp checks that; here only the lower layer is.)
    test::TestWorld w;
    w.addGround();
    Plugin plugin(w.world);
    BodySettings settings;
    settings.deformation = Deformation::Soft;
    VisualBody& body = plugin.addVisualBody(test::cubes(2, 0.1, 0.0, 0.3, 0.01), settings, btTransform::getIdentity());
    ASSERT_EQ(body.warnings().size(), 1u);
    EXPECT_NE(body.warnings()[0].find("8 unconnected parts"), std::string::npos) << body.warnings()[0];
    w.step(240);
    const auto& p = body.solver()->particles();
    for (int i = 0; i < p.size(); ++i)
        if (p.restPosition[i].y() < 0.35) {
            EXPECT_NEAR(p.position[i].y(), 0.04, 2e-3) << i; // landed upright
        }
}

TEST(SoftBody, BadSolverSettingsAreErrorsNamingTheBody) {
    test::TestWorld w;
    Plugin plugin(w.world);
    BodySettings settings;
    settings.deformation = Deformation::Soft;
    settings.solver.stiffness = 2.0;
    try {
        plugin.addVisualBody(test::cubes(2, 0.05, 0.0, 0.1), settings, btTransform::getIdentity());
        FAIL() << "stiffness 2 accepted";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("body 'jelly': stiffness"), std::string::npos) << e.what();
    }
}

} // namespace
} // namespace shatter
