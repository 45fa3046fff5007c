// Position based dynamics with orientations (source 000 §3.2.2): integration, conservation,
// rest states and bad input.
#include "OrientedFixtures.h"
#include <shatter/plugin/common/InputError.h>
#include <shatter/plugin/oriented/ParticleMoment.h>

#include <gtest/gtest.h>
#include <cmath>
#include <utility>

namespace shatter::oriented {
namespace {

using test::cubeBlock;

SolverSettings weightless() {
    SolverSettings s;
    s.gravity.setZero();
    return s;
}

// A deformed block tumbling without external forces for 50 steps: every group projection
// moves its members by Σ m Δx = 0, so Σ m v is kept exactly (to rounding: 1e-9 of the momentum
// scale Σ m|v|), and the sweeps did move the particles.
void expectTumblingBlockKeepsLinearMomentum(const SolverSettings& settings, unsigned seed) {
    std::mt19937 rng(seed);
    auto solver = test::blockSolver(cubeBlock(4, 3, 2, 0.1), settings);
    auto& p = solver.particles();
    for (int i = 0; i < p.size(); ++i) {
        p.position[i] += test::randomVector(rng, 0.01);
        p.velocity[i] = test::randomVector(rng, 1.0);
        p.angularVelocity[i] = test::randomVector(rng, 3.0);
    }
    const Eigen::Vector3d before = p.linearMomentum();
    double scale = 0.0;
    for (int i = 0; i < p.size(); ++i) scale += p.mass[i] * p.velocity[i].norm();
    const auto start = p.position;
    for (int step = 0; step < 50; ++step) solver.step(1.0 / 240);
    EXPECT_LT((p.linearMomentum() - before).norm(), 1e-9 * scale);
    EXPECT_NE(p.position, start);
}

TEST(OrientedSolver, StepKeepsLinearMomentumWithoutExternalForces) {
    expectTumblingBlockKeepsLinearMomentum(weightless(), 1);
}

TEST(OrientedSolver, RigidSpinKeepsAngularMomentumAndEnergy) {
    // A block spinning rigidly about its centre with no forces: shape matching has nothing to
    // correct, so angular momentum (orbital + spin) and kinetic energy stay as they were. The
    // first-order PBD velocity update replaces the circular arc by its chord, which loses
    // (ω dt)²/2 per step of the centripetal motion: over 100 steps at ω dt = 0.01 that is ~1e-2
    // relative at most; the bound is 2e-2.
    auto solver = test::blockSolver(cubeBlock(3, 3, 3, 0.1), weightless());
    auto& p = solver.particles();
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    double M = 0.0;
    for (int i = 0; i < p.size(); ++i) centre += p.mass[i] * p.position[i], M += p.mass[i];
    centre /= M;
    const Eigen::Vector3d omega(0, 0, 2.4);
    for (int i = 0; i < p.size(); ++i) {
        p.velocity[i] = omega.cross(p.position[i] - centre);
        p.angularVelocity[i] = omega;
    }
    const Eigen::Vector3d L0 = p.angularMomentum();
    const double E0 = p.kineticEnergy();
    for (int step = 0; step < 100; ++step) solver.step(1.0 / 240);
    EXPECT_LT((p.angularMomentum() - L0).norm(), 2e-2 * L0.norm());
    EXPECT_LE(p.kineticEnergy(), E0 * (1 + 1e-12)); // never gains
    EXPECT_GT(p.kineticEnergy(), E0 * (1 - 2e-2));
}

TEST(OrientedSolver, ConstantSpinMatchesTheExactRotation) {
    // One cube (isotropic inertia, so a constant ω is the exact torque-free motion), no
    // gravity: after n steps the orientation is exp(ω n dt) q0. Each step composes exact
    // axis-angle rotations, so the error is rounding only: 1e-9 rad after 1,000 steps.
    auto solver = test::blockSolver(cubeBlock(1, 1, 1, 0.2), weightless());
    const Eigen::Vector3d omega(0.3, -1.2, 2.0);
    solver.particles().angularVelocity[0] = omega;
    const double dt = 1e-3;
    for (int step = 0; step < 1000; ++step) solver.step(dt);
    const Eigen::Quaterniond exact(Eigen::AngleAxisd(omega.norm() * 1000 * dt, omega.normalized()));
    EXPECT_LT(solver.particles().orientation[0].angularDistance(exact), 1e-9);
    EXPECT_LT((solver.particles().angularVelocity[0] - omega).norm(), 1e-6 * omega.norm());
}

// Plane z = 0 under a block: each particle's lowest vertex gives one contact.
std::vector<ParticleContact> groundContacts(const OrientedSolver& s, const std::vector<geometry::ConvexPolyhedron>& rest) {
    std::vector<ParticleContact> contacts;
    const auto& p = s.particles();
    for (int i = 0; i < p.size(); ++i) {
        double lowest = std::numeric_limits<double>::infinity();
        for (const auto& v : rest[i].vertices())
            lowest = std::min(lowest, (p.position[i] + p.orientation[i] * (v - p.restPosition[i])).z());
        if (lowest < 0.01) contacts.push_back({i, Eigen::Vector3d::UnitZ(), lowest, 0.8});
    }
    return contacts;
}

// A 4×3×2 block of 5 cm cubes dropped from 1 cm onto the ground, then 10,000 steps at
// 240 Hz (42 s). After it settles: no horizontal drift beyond 1 µm, no energy above the
// settled value, and it never sinks more than the 0.1 mm a single step's gravity
// (g dt² = 0.17 mm) can push it in before the contact catches it.
void expectRestingBlockNeitherDriftsNorGainsEnergy(const SolverSettings& settings) {
    const auto block = cubeBlock(4, 3, 2, 0.05, Eigen::Vector3d(0, 0, 0.01));
    auto solver = test::blockSolver(block, settings);
    auto& p = solver.particles();
    auto energy = [&] {
        double e = p.kineticEnergy();
        for (int i = 0; i < p.size(); ++i) e += p.mass[i] * 9.81 * p.position[i].z();
        return e;
    };
    auto centre = [&] {
        Eigen::Vector3d c = Eigen::Vector3d::Zero();
        double M = 0.0;
        for (int i = 0; i < p.size(); ++i) c += p.mass[i] * p.position[i], M += p.mass[i];
        return Eigen::Vector3d(c / M);
    };
    const double dt = 1.0 / 240;
    for (int step = 0; step < 1000; ++step) solver.step(dt, groundContacts(solver, block.primitives));
    const double settled = energy();
    const Eigen::Vector3d settledCentre = centre();
    double highest = settled, lowestZ = 0.0;
    for (int step = 0; step < 10000; ++step) {
        solver.step(dt, groundContacts(solver, block.primitives));
        highest = std::max(highest, energy());
        for (const auto& c : groundContacts(solver, block.primitives)) lowestZ = std::min(lowestZ, c.distance);
    }
    const Eigen::Vector3d drift = centre() - settledCentre;
    EXPECT_LT(drift.head<2>().norm(), 1e-6);
    EXPECT_LT(std::abs(drift.z()), 1e-4);
    EXPECT_LE(highest, settled + 1e-6 * std::abs(settled) + 1e-9);
    EXPECT_GT(lowestZ, -2e-4);
    EXPECT_LT(p.kineticEnergy(), 1e-9);
}

TEST(OrientedSolver, RestingSoftBlockNeitherDriftsNorGainsEnergy) {
    SolverSettings settings;
    settings.stiffness = 0.5;
    expectRestingBlockNeitherDriftsNorGainsEnergy(settings);
}

TEST(OrientedSolver, RestingSoftBlockWithChebyshevSweepsNeitherDriftsNorGainsEnergy) {
    // The sheet bench's accelerated sweeps (3 of stiffness 0.33, ρ 0.65) at rest on the ground.
    SolverSettings settings;
    settings.iterations = 3;
    settings.stiffness = 0.33;
    settings.chebyshevRadius = 0.65;
    expectRestingBlockNeitherDriftsNorGainsEnergy(settings);
}

TEST(OrientedSolver, ChebyshevSweepsKeepLinearMomentum) {
    // The extrapolated motion Δ_s = ω δ_s + (ω − 1) Δ_{s−1} is made of sweeps' motions with
    // Σ m δ = 0, so Σ m v is kept as by plain sweeps.
    SolverSettings settings = weightless();
    settings.iterations = 3;
    settings.stiffness = 0.33;
    settings.chebyshevRadius = 0.65;
    expectTumblingBlockKeepsLinearMomentum(settings, 5);
}

TEST(OrientedSolver, TheStableChebyshevRadiusKeepsTheStepsOvershootWithinAQuarter) {
    // T_n(1/ρ) = 4 at the bound: the n-sweep step's Chebyshev polynomial swings no lower than
    // −1/4 (SolverSettings.h); no acceleration for 1 sweep, none capped from 5 sweeps.
    const auto chebyshev = [](int n, double x) { return std::cosh(n * std::acosh(x)); };
    EXPECT_EQ(stableChebyshevRadius(1), 0.0);
    EXPECT_NEAR(stableChebyshevRadius(2), std::sqrt(0.4), 1e-15); // 2/ρ² − 1 = 4
    for (int n = 2; n <= 8; ++n) EXPECT_NEAR(chebyshev(n, 1.0 / stableChebyshevRadius(n)), 4.0, 1e-12) << n;
    EXPECT_GT(stableChebyshevRadius(3), 0.8); // the sheet held at 0.8 with 3 sweeps
    EXPECT_GT(stableChebyshevRadius(5), kMaxChebyshevRadius);
}

TEST(OrientedSolver, NoChebyshevRadiusTheSettingsTakeExplodes) {
    // The largest ρ check() takes (maxChebyshevRadius, the divergence bound). A block
    // deformed by 2 cm, let go without gravity or damping: the sweeps only take energy out, so
    // its kinetic energy must never exceed the first step's. Beyond the bound, ρ 0.9 at 2
    // sweeps overshoots every step and the energy reached inf within the 2,000 steps (measured,
    // both stiffnesses); at the bound it falls from about 600 to below 0.1.
    for (const int iterations : {2, 3}) {
        for (const double stiffness : {0.51, 1.0}) {
            std::mt19937 rng(11);
            SolverSettings settings = weightless();
            settings.iterations = iterations;
            settings.stiffness = stiffness;
            settings.chebyshevRadius = maxChebyshevRadius(iterations);
            auto solver = test::blockSolver(cubeBlock(4, 4, 2, 0.1), settings);
            auto& p = solver.particles();
            for (int i = 0; i < p.size(); ++i) p.position[i] += test::randomVector(rng, 0.02);
            solver.step(1.0 / 240);
            const double first = p.kineticEnergy();
            double highest = first;
            for (int step = 0; step < 2000; ++step) {
                solver.step(1.0 / 240);
                highest = std::max(highest, p.kineticEnergy());
            }
            EXPECT_TRUE(std::isfinite(highest)) << iterations << " sweeps of " << stiffness;
            EXPECT_LE(highest, first) << iterations << " sweeps of " << stiffness;
            EXPECT_LT(p.kineticEnergy(), 1e-3 * first) << iterations << " sweeps of " << stiffness;
        }
    }
}

// The largest error of a connected pair's distance against its rest distance (m): 0 in any
// rigid motion of the rest shape.
double restShapeError(const OrientedSolver& solver, const std::vector<std::pair<int, int>>& connections) {
    const auto& p = solver.particles();
    double worst = 0.0;
    for (const auto& [a, b] : connections)
        worst = std::max(worst, std::abs((p.position[a] - p.position[b]).norm() -
                                         (p.restPosition[a] - p.restPosition[b]).norm()));
    return worst;
}

TEST(OrientedSolver, ChebyshevSweepsReachTheRestShapeOfPlainSweepsInFewerSteps) {
    // A 16-cube bar stretched by 20% along its length, let go without gravity and heavily
    // damped (quasi-static). Its stretch is the slow, long-range mode that the acceleration is
    // for: after 20 steps of 3 accelerated sweeps it is much nearer the rest shape than after
    // 20 steps of 3 plain sweeps of the same stiffness (measured: 0.16 mm against 0.61 mm;
    // after 40 steps 1.1 µm against 17 µm), and
    // both end at the rest shape, which is the plain sweeps' answer.
    const auto bar = cubeBlock(16, 1, 1, 0.05);
    auto error = [&](double rho, int steps) {
        SolverSettings settings = weightless();
        settings.iterations = 3;
        settings.stiffness = 0.33;
        settings.damping = 200.0;
        settings.chebyshevRadius = rho;
        auto solver = test::blockSolver(bar, settings);
        auto& p = solver.particles();
        for (int i = 0; i < p.size(); ++i) p.position[i].x() *= 1.2;
        for (int step = 0; step < steps; ++step) solver.step(1.0 / 240);
        return restShapeError(solver, bar.connections);
    };
    const double plain = error(0.0, 20), accelerated = error(0.65, 20);
    EXPECT_GT(plain, 1e-4);
    EXPECT_LT(accelerated, 0.5 * plain);
    EXPECT_LT(error(0.0, 3000), 1e-7);
    EXPECT_LT(error(0.65, 3000), 1e-7);
}

TEST(OrientedSolver, SubstepsWithoutContactsAreThatManySteps) {
    // step(dt, {}, {}, n) is n step(dt)s, bit for bit: a spinning, tumbling, falling block.
    std::mt19937 rng(3);
    auto one = test::blockSolver(cubeBlock(3, 2, 2, 0.1), SolverSettings{});
    for (int i = 0; i < one.particles().size(); ++i) {
        one.particles().velocity[i] = test::randomVector(rng, 1.0);
        one.particles().angularVelocity[i] = test::randomVector(rng, 3.0);
    }
    auto four = one;
    for (int step = 0; step < 12; ++step) one.step(1.0 / 240);
    for (int step = 0; step < 3; ++step) four.step(1.0 / 240, {}, {}, 4);
    EXPECT_EQ(one.particles().position, four.particles().position);
    EXPECT_EQ(one.particles().velocity, four.particles().velocity);
    EXPECT_EQ(one.particles().angularVelocity, four.particles().angularVelocity);
    for (int i = 0; i < one.particles().size(); ++i)
        EXPECT_EQ(one.particles().orientation[i].coeffs(), four.particles().orientation[i].coeffs());
}

TEST(OrientedSolver, SubstepsOnContactsFoundBeforeTheFirstLandAndRestAsWithFreshContacts) {
    // A block dropped from 5 mm lands with its ground contacts found only every 4th step:
    // the later steps see each contact's distance less the particle's fall since, so the
    // block stops on the ground (with the found distance alone it would fall up to that far
    // in each of them). It then rests for 2,400 steps: within 0.1 mm of the block that had
    // fresh contacts every step, no energy gain, and no sinking beyond one step's gravity.
    const auto block = cubeBlock(4, 3, 2, 0.05, Eigen::Vector3d(0, 0, 0.005));
    SolverSettings settings;
    settings.stiffness = 0.5;
    auto fresh = test::blockSolver(block, settings), found = fresh;
    const double dt = 1.0 / 240;
    auto energy = [](const OrientedSolver& s) {
        const auto& p = s.particles();
        double e = p.kineticEnergy();
        for (int i = 0; i < p.size(); ++i) e += p.mass[i] * 9.81 * p.position[i].z();
        return e;
    };
    double lowestZ = 0.0;
    auto lowest = [&](const OrientedSolver& s) {
        for (const auto& c : groundContacts(s, block.primitives)) lowestZ = std::min(lowestZ, c.distance);
    };
    for (int step = 0; step < 240; ++step) {
        fresh.step(dt, groundContacts(fresh, block.primitives));
        if (step % 4 == 0) found.step(dt, groundContacts(found, block.primitives), {}, 4);
        lowest(found);
    }
    const double settled = energy(found);
    double highest = settled;
    for (int step = 0; step < 2400; step += 4) {
        found.step(dt, groundContacts(found, block.primitives), {}, 4);
        highest = std::max(highest, energy(found));
        lowest(found);
    }
    for (int step = 0; step < 2400; ++step) fresh.step(dt, groundContacts(fresh, block.primitives));
    for (int i = 0; i < found.particles().size(); ++i)
        EXPECT_LT((found.particles().position[i] - fresh.particles().position[i]).norm(), 1e-4) << i;
    EXPECT_LE(highest, settled + 1e-6 * std::abs(settled) + 1e-9);
    EXPECT_GT(lowestZ, -2e-4);
}

TEST(OrientedSolver, DampingRemovesEnergyAtTheStatedRate) {
    SolverSettings settings = weightless();
    settings.damping = 2.0; // 1/s
    auto solver = test::blockSolver(cubeBlock(2, 2, 2, 0.1), settings);
    for (auto& v : solver.particles().velocity) v = Eigen::Vector3d(1, 0, 0);
    for (int step = 0; step < 240; ++step) solver.step(1.0 / 240);
    // Uniform translation: shape matching is idle, v(t) = exp(−2 t) after 1 s.
    EXPECT_NEAR(solver.particles().velocity[0].x(), std::exp(-2.0), 1e-12);
}

TEST(OrientedSolver, QuietTimeCountsStepsWithEveryParticleBelowTheSleepSpeed) {
    // A weightless block drifting at 2 cm/s with damping 2/s: its speed is 2 exp(−2 t) cm/s,
    // under the 1 cm/s sleep speed after ln 2 / 2 = 0.347 s; so after 1 s it has been quiet
    // for 0.653 s (to a step), and stop() leaves it at rest. A spin counts as well: a lone
    // 10 cm cube (tr C / m = 3 × 0.1² / 12) spinning at 1 rad/s moves at 5 cm/s by this
    // measure, at 0.1 rad/s at 5 mm/s.
    SolverSettings settings = weightless();
    settings.damping = 2.0;
    settings.sleepSpeed = 0.01;
    auto solver = test::blockSolver(cubeBlock(2, 2, 2, 0.1), settings);
    for (auto& v : solver.particles().velocity) v = Eigen::Vector3d(0.02, 0, 0);
    const double dt = 1.0 / 240;
    for (int step = 0; step < 240; ++step) solver.step(dt);
    EXPECT_NEAR(solver.quietTime(), 1.0 - std::log(2.0) / 2.0, dt);
    solver.stop();
    EXPECT_EQ(solver.particles().kineticEnergy(), 0.0);
    EXPECT_EQ(solver.quietTime(), 0.0);
    settings.damping = 0.0;
    for (const double spin : {1.0, 0.1}) {
        auto cube = test::blockSolver(cubeBlock(1, 1, 1, 0.1), settings);
        cube.particles().angularVelocity[0] = Eigen::Vector3d(0, 0, spin);
        cube.step(dt);
        EXPECT_EQ(cube.quietTime(), spin == 1.0 ? 0.0 : dt) << spin;
    }
}

TEST(OrientedSolver, BadSettingsAndContactsAreErrorsNamingTheObject) {
    const auto block = cubeBlock(2, 1, 1, 0.1);
    for (double stiffness : {-0.1, 1.5, std::nan("")}) {
        SolverSettings s;
        s.stiffness = stiffness;
        try {
            test::blockSolver(block, s);
            FAIL() << "stiffness " << stiffness << " accepted";
        } catch (const InputError& e) {
            EXPECT_NE(std::string(e.what()).find("body 'block': stiffness must be in [0, 1]"), std::string::npos)
                << e.what();
        }
    }
    // At the default 4 sweeps the bound is 0.880; at 3, 0.802 (the sheet blew up at 0.9).
    const std::pair<int, double> badRadii[] = {
        {4, -0.1}, {4, maxChebyshevRadius(4) + 0.01}, {4, std::nan("")}, {3, 0.85}, {2, 0.7}, {8, 0.91}};
    for (const auto& [iterations, rho] : badRadii) {
        SolverSettings s;
        s.iterations = iterations;
        s.chebyshevRadius = rho;
        try {
            test::blockSolver(block, s);
            FAIL() << "Chebyshev radius " << rho << " accepted at " << iterations << " sweeps";
        } catch (const InputError& e) {
            const std::string expected =
                "body 'block': Chebyshev radius at " + std::to_string(iterations) + " sweeps must be in [0, ";
            EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
        }
    }
    for (double speed : {-0.01, std::nan("")}) {
        SolverSettings s;
        s.sleepSpeed = speed;
        try {
            test::blockSolver(block, s);
            FAIL() << "sleep speed " << speed << " accepted";
        } catch (const InputError& e) {
            EXPECT_NE(std::string(e.what()).find("body 'block': sleep speed (m/s)"), std::string::npos) << e.what();
        }
    }
    {
        SolverSettings s;
        s.substepsPerStep = 0;
        try {
            test::blockSolver(block, s);
            FAIL() << "0 substeps per step accepted";
        } catch (const InputError& e) {
            EXPECT_NE(std::string(e.what()).find("body 'block': substeps per step"), std::string::npos) << e.what();
        }
    }
    auto solver = test::blockSolver(block);
    const ParticleContact nan{0, Eigen::Vector3d(0, 0, std::nan("")), 0.0, 0.5};
    EXPECT_THROW(solver.step(1e-3, std::span(&nan, 1)), InputError);
    const ParticleContact unknown{7, Eigen::Vector3d::UnitZ(), 0.0, 0.5};
    EXPECT_THROW(solver.step(1e-3, std::span(&unknown, 1)), InputError);
    EXPECT_THROW(solver.step(0.0), InputError);
    EXPECT_THROW(solver.step(1e-3, {}, {}, 0), InputError);
    // Several substeps take the other side as standing still.
    ParticleContact moving{0, Eigen::Vector3d::UnitZ(), 0.0, 0.5};
    moving.surfaceMove = Eigen::Vector3d(0, 0, 1e-3);
    try {
        solver.step(1e-3, std::span(&moving, 1), {}, 2);
        FAIL() << "a moving surface accepted in a step of 2 substeps";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("object 'block': contact 0 (particle 0) names a body or a moving surface"),
                  std::string::npos)
            << e.what();
    }
}

TEST(OrientedSolver, BodyContactsShareEveryCorrectionSoMomentumIsKept) {
    // A block moving at 1 m/s into a 2 kg body 1 mm ahead (no gravity): the contacts move the
    // particles and the body by equal and opposite Σ m Δx, so the block's momentum change is
    // the body's (shift / dt times its mass), to rounding.
    auto solver = test::blockSolver(cubeBlock(2, 2, 2, 0.1), weightless());
    auto& p = solver.particles();
    for (auto& v : p.velocity) v = Eigen::Vector3d(1, 0, 0);
    std::vector<ParticleContact> contacts;
    for (int i = 0; i < p.size(); ++i) {
        if (p.position[i].x() < 0.1) continue; // the front layer
        ParticleContact c;
        c.particle = i;
        c.normal = -Eigen::Vector3d::UnitX(); // from the body into the particle
        c.distance = 0.001;
        c.body = 0;
        c.point = p.position[i] + Eigen::Vector3d(0.051, 0, 0);
        c.friction = 0.0;
        contacts.push_back(c);
    }
    ContactBody body;
    body.inverseMass = 0.5;
    body.inverseInertia = 10.0 * Eigen::Matrix3d::Identity();
    body.centre = Eigen::Vector3d(0.2, 0.1, 0.1);
    const double dt = 1.0 / 60;
    const Eigen::Vector3d before = p.linearMomentum();
    solver.step(dt, contacts, std::span(&body, 1));
    const Eigen::Vector3d bodyMomentum = body.shift / dt / body.inverseMass;
    EXPECT_GT(bodyMomentum.x(), 0.1 * before.x()); // the body was really pushed
    EXPECT_LT((p.linearMomentum() + bodyMomentum - before).norm(), 1e-9 * before.norm());
    // The contacts' impulses are what the body lost: Σ impulse on the particles = −its momentum.
    ASSERT_EQ(solver.contactImpulses().size(), contacts.size());
    Eigen::Vector3d impulse = Eigen::Vector3d::Zero();
    for (const Eigen::Vector3d& j : solver.contactImpulses()) impulse += j;
    EXPECT_LT((impulse + bodyMomentum).norm(), 1e-9 * bodyMomentum.norm());
}

TEST(OrientedSolver, BadContactBodiesAreErrorsNamingTheObject) {
    auto solver = test::blockSolver(cubeBlock(2, 1, 1, 0.1));
    ContactBody negative;
    negative.inverseMass = -1.0;
    try {
        solver.step(1e-3, {}, std::span(&negative, 1));
        FAIL() << "negative inverse mass accepted";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("object 'block': contact body 0"), std::string::npos) << e.what();
    }
    ParticleContact missing;
    missing.body = 3;
    EXPECT_THROW(solver.step(1e-3, std::span(&missing, 1)), InputError);
    ParticleContact self;
    self.otherParticle = 0;
    EXPECT_THROW(solver.step(1e-3, std::span(&self, 1)), InputError);
}

TEST(OrientedSolver, ZeroMassPrimitiveIsAnErrorNamingTheObject) {
    const auto block = cubeBlock(2, 1, 1, 0.1);
    try {
        particlesFromPrimitives(block.primitives, 0.0, "door");
        FAIL() << "zero density accepted";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("object 'door': primitive 0 has mass 0"), std::string::npos) << e.what();
    }
}

TEST(OrientedSolver, StretchAndBendConstraintsRestoreTheirRestValues) {
    auto solver = test::blockSolver(cubeBlock(2, 1, 1, 0.1), weightless());
    auto& p = solver.particles();
    p.position[1] += Eigen::Vector3d(0.05, 0.02, 0);
    p.orientation[1] = Eigen::Quaterniond(Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitZ()));
    const StretchConstraint stretch{0, 1, 0.1, 1.0};
    const BendConstraint bend{0, 1, 1.0};
    const Eigen::Vector3d momentumBefore = p.mass[0] * p.position[0] + p.mass[1] * p.position[1];
    stretch.project(p, p.position);
    bend.project(p, p.orientation);
    EXPECT_NEAR((p.position[1] - p.position[0]).norm(), 0.1, 1e-12);
    EXPECT_LT((p.mass[0] * p.position[0] + p.mass[1] * p.position[1] - momentumBefore).norm(), 1e-12);
    EXPECT_LT(p.orientation[0].angularDistance(p.orientation[1]), 1e-9);
}

TEST(OrientedSolver, RebuiltSolverStepsAsANewOneBuiltFromTheSameArguments) {
    // A torn body that keeps a part rebuilds its solver in place (VisualBody::keepPart): no
    // trace of the old solver may remain, neither its groups' warm starts nor its constraints,
    // last step (second-order velocities), quiet time or per-step buffers (more particles).
    SolverSettings settings;
    settings.secondOrderVelocity = true;
    settings.damping = 0.5;
    settings.sleepSpeed = 10.0; // every step quiet: the quiet time counts from the rebuild
    auto rebuilt = test::blockSolver(cubeBlock(5, 4, 2, 0.1), settings);
    std::mt19937 rng(5);
    for (auto& v : rebuilt.particles().velocity) v = test::randomVector(rng, 0.5);
    rebuilt.stretchConstraints().push_back({0, 1, 0.1, 1.0});
    rebuilt.bendConstraints().push_back({0, 1, 1.0});
    const ParticleContact floor{0, Eigen::Vector3d::UnitZ(), -0.001, 0.5};
    for (int step = 0; step < 5; ++step) rebuilt.step(1.0 / 240, std::span(&floor, 1));
    ASSERT_GT(rebuilt.quietTime(), 0.0);
    const auto before = rebuilt.groups().connectionsVersion();

    const auto block = cubeBlock(3, 2, 2, 0.1, Eigen::Vector3d(0.3, 0, 0));
    settings.damping = 0.25;
    const OrientedParticles particles = particlesFromPrimitives(block.primitives, 900.0, "block.1");
    rebuilt.rebuild("block.1", particles, block.connections, settings);
    OrientedSolver built("block.1", particles, block.connections, settings);
    EXPECT_NE(rebuilt.groups().connectionsVersion(), before);
    EXPECT_EQ(rebuilt.object(), "block.1");
    EXPECT_TRUE(rebuilt.stretchConstraints().empty());
    EXPECT_TRUE(rebuilt.bendConstraints().empty());
    EXPECT_EQ(rebuilt.quietTime(), 0.0);
    for (OrientedSolver* s : {&rebuilt, &built})
        for (int i = 0; i < s->particles().size(); ++i) s->particles().velocity[i] = Eigen::Vector3d(0.01 * i, 0, -0.2);
    for (int step = 0; step < 10; ++step) {
        rebuilt.step(1.0 / 240);
        built.step(1.0 / 240);
    }
    const OrientedParticles &a = rebuilt.particles(), &b = built.particles();
    ASSERT_EQ(a.size(), b.size());
    for (int i = 0; i < a.size(); ++i) {
        EXPECT_EQ(a.position[i], b.position[i]) << "particle " << i;
        EXPECT_TRUE(a.orientation[i].coeffs() == b.orientation[i].coeffs()) << "particle " << i;
        EXPECT_EQ(a.velocity[i], b.velocity[i]) << "particle " << i;
        EXPECT_EQ(a.angularVelocity[i], b.angularVelocity[i]) << "particle " << i;
    }
    for (int g = 0; g < built.groups().size(); ++g)
        EXPECT_TRUE(rebuilt.groups().rotation(g).coeffs() == built.groups().rotation(g).coeffs()) << "group " << g;
    EXPECT_EQ(rebuilt.quietTime(), built.quietTime());
}

TEST(OrientedSolver, ARebuildWithBadInputNamesTheObjectAndChangesNothing) {
    auto solver = test::blockSolver(cubeBlock(2, 2, 1, 0.1));
    const auto version = solver.groups().connectionsVersion();
    const auto block = cubeBlock(2, 1, 1, 0.1);
    const OrientedParticles particles = particlesFromPrimitives(block.primitives, 1000.0, "part");
    SolverSettings bad;
    bad.stiffness = 2.0;
    try {
        solver.rebuild("part", particles, block.connections, bad);
        FAIL() << "stiffness 2 accepted";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("body 'part': stiffness"), std::string::npos) << e.what();
    }
    EXPECT_THROW(solver.rebuild("part", particles, {{0, 2}}, {}), InputError);
    EXPECT_EQ(solver.object(), "block");
    EXPECT_EQ(solver.particles().size(), 4);
    EXPECT_EQ(solver.groups().size(), 4);
    EXPECT_EQ(solver.groups().connectionsVersion(), version);
}

} // namespace
} // namespace shatter::oriented
