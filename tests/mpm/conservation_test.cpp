// Conservation and rest: the MPM core against Newton's laws, without cracks.
#include "TestScenes.h"
#include <shatter/plugin/mpm/Diagnostics.h>
#include <shatter/plugin/mpm/Solver2D.h>

#include <gtest/gtest.h>

#include <cmath>

namespace shatter::mpm {
namespace {

using test::diskScene;
using test::elastic;

// A spinning, translating jello-like disk (E 1e5 Pa, ρ 1000: wave speed 10 m/s, so the
// CFL step with dx = 0.1 m is about 4 ms and a second is ~250 substeps).
Scene spinningDisk(VelocityTransfer transfer) {
    Scene s = diskScene(0.1, elastic(ConstitutiveModelType::Corotated, 1e5, 0.3, 1000), Vec2(1, 1), 0.5,
                        Vec2(0.7, -0.4));
    s.transfer = transfer;
    return s;
}

// Gives every particle of the solver the rigid velocity v0 + ω × (x − c).
void spin(Solver2D& solver, Vec2 v0, double omega, Vec2 centre) {
    auto& P = solver.mutableParticles();
    for (size_t p = 0; p < P.size(); ++p) {
        const Vec2 r = P.x[p] - centre;
        P.v[p] = v0 + omega * Vec2(-r.y(), r.x());
        P.C[p] << 0, -omega, omega, 0;
    }
}

TEST(Conservation, MassIsExactOnParticlesAndOnTheGrid) {
    Scene s = spinningDisk(VelocityTransfer::Apic);
    s.gravity = Vec2(0, -9.81);
    s.colliders.push_back(test::ground(0.45));
    Solver2D solver(s);
    const double m0 = totals(solver).mass;
    for (int k = 0; k < 50; ++k) {
        solver.step(1.0);
        // Particle masses never change (exact); the grid holds the same mass up to the
        // rounding of the partition of unity (~1e-15 per weight).
        EXPECT_EQ(totals(solver).mass, m0);
        EXPECT_NEAR(gridMass(solver), m0, 1e-12 * m0);
    }
}

TEST(Conservation, MomentumIsConservedInFreeFlight) {
    for (auto transfer : {VelocityTransfer::Apic, VelocityTransfer::Pic}) {
        Solver2D solver(spinningDisk(transfer));
        spin(solver, Vec2(0.7, -0.4), 2.0, Vec2(1, 1));
        const Totals before = totals(solver);
        solver.advance(0.5);
        const Totals after = totals(solver);
        // Linear momentum: the transfers conserve it exactly but for rounding.
        EXPECT_NEAR((after.momentum - before.momentum).norm(), 0, 1e-11 * before.momentum.norm());
        if (transfer == VelocityTransfer::Apic) {
            // APIC conserves angular momentum too (Jiang et al. 2015); the explicit position
            // update x += Δt v grows the radius by O(Δt²ω²) per step, hence a small drift.
            EXPECT_NEAR(after.angularMomentum, before.angularMomentum, 1e-3 * std::abs(before.angularMomentum));
        }
    }
}

TEST(Conservation, MomentumChangesByExactlyTheWeightUnderGravity) {
    Scene s = spinningDisk(VelocityTransfer::Apic);
    s.gravity = Vec2(0, -9.81);
    Solver2D solver(s);
    const Totals before = totals(solver);
    solver.advance(0.25);
    const Totals after = totals(solver);
    const Vec2 expected = before.momentum + before.mass * s.gravity * solver.time();
    EXPECT_NEAR((after.momentum - expected).norm(), 0, 1e-11 * expected.norm());
}

TEST(Conservation, RigidTranslationAndRotationProduceNoStress) {
    for (auto type : {ConstitutiveModelType::Corotated, ConstitutiveModelType::Snow}) {
        Scene s = spinningDisk(VelocityTransfer::Apic);
        s.materials[0].model = type;
        Solver2D solver(s);
        const double omega = 2.0;
        spin(solver, Vec2(0.7, -0.4), omega, Vec2(1, 1));
        solver.advance(0.5);
        double worst = 0;
        for (size_t p = 0; p < solver.particles().size(); ++p)
            worst = std::max(worst, solver.cauchyStress(p).norm());
        // APIC carries a rigid velocity field exactly, so F advances by (I + Δt W) with W the
        // spin: a rotation times an isotropic stretch of 1 + ½(Δtω)² per step, the error of
        // the explicit update (eq. 13). Over n steps of mean Δt = T/n that is a strain
        // ε = ½ω²T²/n and, for the corotated law, a stress of about 2(λ + μ)ε per diagonal
        // entry. Anything beyond 1.5 times that would be stress made by the transfers.
        const double lambda = s.materials[0].lameLambda(s.analysis), mu = s.materials[0].shearModulus();
        const double eps = 0.5 * omega * omega * 0.25 / double(solver.substeps());
        const double integratorStress = std::sqrt(2.0) * 2 * (lambda + mu) * eps;
        EXPECT_LT(worst, 1.5 * integratorStress) << int(type);
        EXPECT_LT(integratorStress, 1e-2 * s.materials[0].E); // and that error is small
    }
    {
        // Pure translation: every step is exact, stress stays zero to rounding.
        Scene s = spinningDisk(VelocityTransfer::Apic);
        s.materials[0].model = ConstitutiveModelType::LinearElastic;
        Solver2D solver(s);
        solver.advance(0.5);
        for (size_t p = 0; p < solver.particles().size(); ++p) EXPECT_LT(solver.cauchyStress(p).norm(), 1e-9);
    }
}

TEST(Conservation, BodyAtRestOnTheGroundStaysAtRest) {
    // A 1 m x 0.5 m block (E 1e7, ρ 1000) standing on the ground under gravity. Its static
    // sag is ρgH/E ≈ 5e-4 of its height; elastic ringing then has velocities of order
    // c·ρgH/E ≈ 100 m/s · 5e-4 = 0.05 m/s at most, against 4.9 m/s of free fall in 0.5 s.
    Scene s = test::baseScene(0.05, elastic(ConstitutiveModelType::Corotated, 1e7, 0.3, 1000));
    s.bodies.push_back(Body{Shape(RectShape{Vec2(0, 0), Vec2(1, 0.5)}), 0, Vec2::Zero()});
    s.gravity = Vec2(0, -9.81);
    s.colliders.push_back(test::ground(0));
    Solver2D solver(s);
    const Totals start = totals(solver);
    double fastest = 0;
    for (int frame = 0; frame < 10; ++frame) {
        solver.advance(0.05);
        const Totals t = totals(solver);
        fastest = std::max(fastest, t.momentum.norm() / t.mass);
        // It neither sinks into the ground nor jumps: the centre of mass moves less than a
        // tenth of a cell.
        EXPECT_LT((t.centreOfMass - start.centreOfMass).norm(), 0.1 * s.grid.dx) << frame;
    }
    EXPECT_LT(fastest, 0.05);
}

TEST(Conservation, DropGainsNoEnergy) {
    // A disk dropped 0.3 m onto the ground: kinetic + elastic + gravitational energy may only
    // fall (collisions and APIC dissipate). 2e-3 of the drop energy allows for the discrete
    // energy of the explicit step, which is not exactly the continuous one.
    Scene s = diskScene(0.05, elastic(ConstitutiveModelType::Corotated, 1e6, 0.3, 1000), Vec2(0, 0.8), 0.4,
                        Vec2::Zero());
    s.gravity = Vec2(0, -9.81);
    s.colliders.push_back(test::ground(0));
    Solver2D solver(s);
    const double e0 = totals(solver).total();
    const double dropEnergy = totals(solver).mass * 9.81 * 0.4; // to the bottom of the disk
    double highest = e0;
    bool touched = false;
    for (int frame = 0; frame < 40; ++frame) {
        solver.advance(0.02);
        const Totals t = totals(solver);
        highest = std::max(highest, t.total());
        touched = touched || t.elastic > 0.01 * dropEnergy;
    }
    EXPECT_TRUE(touched); // the disk did hit the ground
    EXPECT_LT(highest - e0, 2e-3 * dropEnergy);
}

TEST(Conservation, ParticlesAddedInCodeJoinTheNextStep) {
    // A particle added through mutableParticles() far above the disk: the solver sizes its
    // per-particle arrays to it, and it falls freely (its kernel touches no other particle,
    // so the transfers carry it exactly): v = g t, and x = x0 + g t²/2 up to the integrator's
    // first-order lag, g t²/(2N) after N substeps (x moves with the new velocity).
    Scene s = spinningDisk(VelocityTransfer::Apic);
    s.gravity = Vec2(0, -9.81);
    Solver2D solver(s);
    const size_t added = solver.particles().size();
    const double m = solver.particles().mass[0], v0 = solver.particles().volume0[0];
    solver.mutableParticles().add(Vec2(5, 5), Vec2::Zero(), m, v0, 0, 0);
    const double mass0 = totals(solver).mass;
    const double t = 0.2;
    solver.advance(t);
    EXPECT_EQ(totals(solver).mass, mass0);
    EXPECT_NEAR(solver.particles().v[added].y(), -9.81 * t, 1e-9);
    const double lag = 0.5 * 9.81 * t * t / double(solver.substeps());
    EXPECT_NEAR(solver.particles().x[added].y(), 5 - 0.5 * 9.81 * t * t - lag, 0.1 * lag);
    EXPECT_NEAR(solver.particles().x[added].x(), 5, 1e-12);
}

TEST(Determinism, SameResultForOneAndTwoThreads) {
    Scene s = spinningDisk(VelocityTransfer::Apic);
    s.gravity = Vec2(0, -9.81);
    s.colliders.push_back(test::ground(0.45));
    Solver2D one(s), two(s);
    one.setThreads(1);
    two.setThreads(2, false); // fixed: the adaptive count could fall back to one
    for (auto* solver : {&one, &two}) solver->advance(0.2);
    ASSERT_EQ(one.substeps(), two.substeps());
    for (size_t p = 0; p < one.particles().size(); ++p) {
        ASSERT_EQ(one.particles().x[p], two.particles().x[p]) << p;
        ASSERT_EQ(one.particles().Fe[p], two.particles().Fe[p]) << p;
    }
}

} // namespace
} // namespace shatter::mpm
