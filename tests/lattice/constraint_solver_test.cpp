// Constraint forces (source 002 eqs. 5-14) checked against statics and linear algebra.
#include "LatticeFixtures.h"
#include <shatter/plugin/common/InputError.h>
#include <shatter/plugin/lattice/ConstraintSolver.h>
#include <shatter/plugin/lattice/EigenvalueBound.h>
#include <shatter/plugin/lattice/LatticePiece.h>
#include <shatter/plugin/lattice/TetGenerators.h>

#include <Eigen/Dense>
#include <Eigen/SparseCholesky>
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <unordered_map>

namespace shatter::lattice {
namespace {

std::vector<int> allParticles(const Lattice& l) { return test::indices(l.particleCount()); }
std::vector<int> allLinks(const Lattice& l) { return test::indices(l.linkCount()); }
ConstraintSystem wholeSystem(const Lattice& l) { return {l, allParticles(l), allLinks(l)}; }

Eigen::VectorXd gravityLoads(const Lattice& l, const ConstraintSystem& s, double g = 9.81) {
    Eigen::VectorXd q = Eigen::VectorXd::Zero(3 * s.particleCount());
    for (int i = 0; i < s.particleCount(); ++i) q[3 * i + 1] = -g * l.particles()[s.particles()[i]].mass;
    return q;
}

Lattice jitteredBox(int nx = 6, int ny = 4, int nz = 3) {
    GeneratorOptions o;
    o.jitter = 0.2;
    o.seed = 3;
    return Lattice(tetBox({1.2, 0.8, 0.6}, {nx, ny, nz}, o), adobe());
}

TEST(ConstraintSolver, JacobianVanishesForRigidMotions) {
    const Lattice lattice = jitteredBox();
    const ConstraintSystem system = wholeSystem(lattice);
    const Eigen::Vector3d v(0.3, -1.7, 2.2), w(-4.0, 1.5, 0.7);
    Eigen::VectorXd translation(3 * system.particleCount()), rotation(3 * system.particleCount());
    for (int i = 0; i < system.particleCount(); ++i) {
        translation.segment<3>(3 * i) = v;
        rotation.segment<3>(3 * i) = w.cross(lattice.particles()[i].position);
    }
    // Exact zero up to rounding of products of O(1) numbers.
    EXPECT_LT(system.jacobianTimes(translation).cwiseAbs().maxCoeff(), 1e-14);
    EXPECT_LT(system.jacobianTimes(rotation).cwiseAbs().maxCoeff(), 1e-14);
}

TEST(ConstraintSolver, JacobianIsTheDerivativeOfTheLinkLengths) {
    // Central differences of C(q + εv) against J v: catches a wrong sign, scale or index.
    const Lattice lattice = jitteredBox(3, 2, 2);
    const ConstraintSystem system = wholeSystem(lattice);
    Eigen::VectorXd v = Eigen::VectorXd::Zero(3 * system.particleCount());
    for (int i = 0; i < v.size(); ++i) v[i] = std::sin(1.7 * i + 0.3);
    const double eps = 1e-6;
    const Eigen::VectorXd jv = system.jacobianTimes(v);
    for (int k = 0; k < system.rowCount(); ++k) {
        const Link& l = lattice.links()[system.links()[k]];
        auto length = [&](double s) {
            const Eigen::Vector3d pa = lattice.particles()[l.a].position + s * v.segment<3>(3 * l.a);
            const Eigen::Vector3d pb = lattice.particles()[l.b].position + s * v.segment<3>(3 * l.b);
            return (pa - pb).norm();
        };
        EXPECT_NEAR((length(eps) - length(-eps)) / (2 * eps), jv[k], 1e-8);
    }
}

// Tension of a link (λ < 0 is tension; see ConstraintSolver.h).
TEST(ConstraintSolver, HangingChainCarriesTheWeightBelowEachLink) {
    const int n = 12;
    Lattice chain(test::verticalChain(n), adobe());
    chain.setFixed(n - 1, true); // the top tet hangs from a support
    const ConstraintSystem system = wholeSystem(chain);
    Eigen::VectorXd lambda;
    ConstraintSolverSettings settings;
    settings.tolerance = 1e-13;
    const SolveResult r = system.solve(system.rightHandSide(gravityLoads(chain, system), Eigen::Vector3d::Zero()),
                                       lambda, settings);
    ASSERT_TRUE(r.converged);
    for (int k = 0; k < system.rowCount(); ++k) {
        const Link& l = chain.links()[system.links()[k]];
        const int lower = std::min(l.a, l.b); // particles are numbered bottom up
        double below = 0.0;
        for (int i = 0; i <= lower; ++i) below += chain.particles()[i].mass * 9.81;
        EXPECT_NEAR(-lambda[k], below, 1e-6 * below) << "link " << k;
    }
}

TEST(ConstraintSolver, StandingChainCarriesTheWeightAboveEachLink) {
    const int n = 12;
    Lattice chain(test::verticalChain(n), brick());
    chain.setFixed(0, true); // the bottom tet rests on the ground
    const ConstraintSystem system = wholeSystem(chain);
    Eigen::VectorXd lambda;
    ConstraintSolverSettings settings;
    settings.tolerance = 1e-13;
    system.solve(system.rightHandSide(gravityLoads(chain, system), Eigen::Vector3d::Zero()), lambda, settings);
    for (int k = 0; k < system.rowCount(); ++k) {
        const Link& l = chain.links()[system.links()[k]];
        const int upper = std::max(l.a, l.b);
        double above = 0.0;
        for (int i = upper; i < n; ++i) above += chain.particles()[i].mass * 9.81;
        EXPECT_NEAR(lambda[k], above, 1e-6 * above) << "link " << k; // compression
    }
}

TEST(ConstraintSolver, FreeBodyUnderGravityAloneHasNoLinkForces) {
    // Uniform gravity accelerates every particle alike: nothing for the links to hold.
    const Lattice lattice = jitteredBox();
    const ConstraintSystem system = wholeSystem(lattice);
    const Eigen::VectorXd b = system.rightHandSide(gravityLoads(lattice, system), Eigen::Vector3d::Zero());
    EXPECT_LT(b.cwiseAbs().maxCoeff(), 1e-12);
}

TEST(ConstraintSolver, SpinningBodyHoldsTheCentripetalForce) {
    // Two particles spinning about their centre of mass: the link pulls each with m ω² r.
    const Lattice pair(makeTetMesh("pair", {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}},
                                   {{0, 1, 2, 3}, {1, 4, 2, 3}}),
                       glass());
    const ConstraintSystem system = wholeSystem(pair);
    const Eigen::Vector3d w = Eigen::Vector3d(0.2, -1.0, 0.5).normalized() * 7.0;
    Eigen::VectorXd lambda;
    ConstraintSolverSettings settings;
    settings.tolerance = 1e-14;
    system.solve(system.rightHandSide(Eigen::VectorXd::Zero(6), w), lambda, settings);
    const Particle& a = pair.particles()[0];
    const Particle& b = pair.particles()[1];
    const double reduced = a.mass * b.mass / (a.mass + b.mass);
    const Eigen::Vector3d d = a.position - b.position;
    const double expected = reduced * w.cross(d).squaredNorm() / d.norm(); // μ |ω × d|² / |d|
    EXPECT_NEAR(-lambda[0], expected, 1e-12 * expected);
}

// The matrix-free product J M⁻¹ Jᵀ x that CG uses is the assembled matrix's (the one the
// eigenvalue bound factorises), also with broken links left out of the system.
TEST(ConstraintSolver, ProductIsTheAssembledMatrixs) {
    Lattice wall = jitteredBox(8, 6, 3);
    for (int t : tetsWithFaceOnPlane(wall.mesh(), {0, 1, 0}, -0.4, 1e-9)) wall.setFixed(t, true);
    for (int k = 0; k < wall.linkCount(); k += 5) wall.breakLink(k);
    const ConstraintSystem system = wholeSystem(wall);
    ASSERT_LT(system.rowCount(), wall.linkCount());
    std::mt19937 random(7);
    std::uniform_real_distribution<double> uniform(-1e3, 1e3);
    Eigen::VectorXd x(system.rowCount());
    for (auto& v : x) v = uniform(random);
    Eigen::VectorXd y;
    system.multiply(x, y);
    const Eigen::VectorXd assembled = system.assemble() * x;
    EXPECT_LT((y - assembled).norm(), 1e-12 * assembled.norm());
}

TEST(ConstraintSolver, ResidualBelowToleranceAndLambdaConvergesToTheDirectSolution) {
    Lattice wall = jitteredBox(8, 6, 3);
    for (int t : tetsWithFaceOnPlane(wall.mesh(), {0, 1, 0}, -0.4, 1e-9)) wall.setFixed(t, true);
    const ConstraintSystem system = wholeSystem(wall);
    Eigen::VectorXd q = gravityLoads(wall, system);
    q.segment<3>(3 * (system.particleCount() / 2)) += Eigen::Vector3d(3e4, 1e4, -5e4); // an impact
    const Eigen::VectorXd b = system.rightHandSide(q, Eigen::Vector3d::Zero());
    // Reference: the dense minimum-norm solution (complete orthogonal decomposition).
    const Eigen::MatrixXd dense(system.assemble());
    const Eigen::VectorXd exact = dense.completeOrthogonalDecomposition().solve(b);
    std::vector<double> errors;
    ConstraintSolverSettings settings;
    settings.tolerance = 1e-10;
    settings.onIteration = [&](int, const Eigen::VectorXd& x, double) { errors.push_back((x - exact).norm()); };
    Eigen::VectorXd lambda;
    const SolveResult r = system.solve(b, lambda, settings);
    ASSERT_TRUE(r.converged) << r.iterations << " iterations, residual " << r.residual;
    EXPECT_LE(r.residual, 1e-10);
    Eigen::VectorXd check;
    system.multiply(lambda, check);
    EXPECT_LE((b - check).norm(), 1e-10 * b.norm() * 1.0001);
    // CG's error decreases monotonically in the Euclidean norm (Hestenes-Stiefel); allow
    // rounding at the bottom.
    for (size_t i = 1; i < errors.size(); ++i) EXPECT_LE(errors[i], errors[i - 1] * (1 + 1e-9) + 1e-9 * exact.norm());
    EXPECT_LT((lambda - exact).norm(), 1e-6 * exact.norm());
}

TEST(ConstraintSolver, RedundantLinksGetTheMinimumNormForces) {
    // A tet whose four neighbours are fixed: four links on three degrees of freedom.
    Lattice star(test::starOfFive(), concrete());
    for (int i = 1; i < 5; ++i) star.setFixed(i, true);
    const ConstraintSystem system = wholeSystem(star);
    ASSERT_EQ(system.rowCount(), 4);
    Eigen::VectorXd q = Eigen::VectorXd::Zero(15);
    q.segment<3>(0) = Eigen::Vector3d(100.0, -250.0, 40.0);
    const Eigen::VectorXd b = system.rightHandSide(q, Eigen::Vector3d::Zero());
    const Eigen::MatrixXd a(system.assemble());
    EXPECT_EQ(a.completeOrthogonalDecomposition().rank(), 3);
    const Eigen::VectorXd minimum = a.completeOrthogonalDecomposition().solve(b);
    ConstraintSolverSettings settings;
    settings.tolerance = 1e-14;
    Eigen::VectorXd lambda;
    system.solve(b, lambda, settings);
    EXPECT_LT((lambda - minimum).norm(), 1e-10 * minimum.norm());
    // The forces hold the particle: Jᵀλ balances the load on the free tet.
    EXPECT_LT((system.constraintForces(lambda).segment<3>(0) + q.segment<3>(0)).norm(), 1e-9 * q.norm());
    // Warm-started from a λ in the range of the matrix (a solution for another load), CG
    // still ends at the minimum-norm solution.
    Eigen::VectorXd warm = a * Eigen::VectorXd::Constant(4, 3.0);
    system.solve(b, warm, settings);
    EXPECT_LT((warm - minimum).norm(), 1e-10 * minimum.norm());
}

TEST(ConstraintSolver, WarmStartConvergesInFewerIterations) {
    Lattice wall = jitteredBox(8, 6, 3);
    for (int t : tetsWithFaceOnPlane(wall.mesh(), {0, 1, 0}, -0.4, 1e-9)) wall.setFixed(t, true);
    const ConstraintSystem system = wholeSystem(wall);
    const Eigen::VectorXd b = system.rightHandSide(gravityLoads(wall, system), Eigen::Vector3d::Zero());
    Eigen::VectorXd lambda;
    const SolveResult cold = system.solve(b, lambda, {});
    const SolveResult warm = system.solve(1.001 * b, lambda, {});
    EXPECT_GT(cold.iterations, 10);
    EXPECT_LT(warm.iterations, cold.iterations);
    EXPECT_TRUE(warm.converged);
}

TEST(ConstraintSolver, AWarmSolveAfterAnImpactSolvesAroundItToTheSameForces) {
    // A wall of 9,600 tets at rest under gravity, then hit at one particle at a top corner.
    Lattice wall = jitteredBox(40, 10, 4);
    for (int t : tetsWithFaceOnPlane(wall.mesh(), {0, 1, 0}, -0.4, 1e-9)) wall.setFixed(t, true);
    const ConstraintSystem system = wholeSystem(wall);
    Eigen::VectorXd q = gravityLoads(wall, system);
    Eigen::VectorXd lambda;
    const SolveResult rest = system.solve(system.rightHandSide(q, Eigen::Vector3d::Zero()), lambda, {});
    ASSERT_TRUE(rest.converged);
    EXPECT_EQ(rest.rowsSolved, system.rowCount()); // a cold start solves every row
    auto height = [&](int i) { return wall.particles()[system.particles()[i]].position.sum(); };
    int hit = 0;
    for (int i = 0; i < system.particleCount(); ++i)
        if (height(i) > height(hit)) hit = i;
    q.segment<3>(3 * hit) += Eigen::Vector3d(2e3, -1e3, -4e3);
    const Eigen::VectorXd b = system.rightHandSide(q, Eigen::Vector3d::Zero());
    const SolveResult warm = system.solve(b, lambda, {});
    ASSERT_TRUE(warm.converged);
    EXPECT_LT(warm.rowsSolved, system.rowCount() / 3); // measured: 4,904 of 17,840
    // Same stopping rule as a solve over every row...
    Eigen::VectorXd check;
    system.multiply(lambda, check);
    EXPECT_LE((b - check).norm(), 1e-6 * b.norm());
    // ...and the same link forces as a cold solve of every row, to the solver's tolerance.
    Eigen::VectorXd cold;
    ConstraintSolverSettings tight;
    tight.tolerance = 1e-10;
    system.solve(b, cold, tight);
    EXPECT_LT((lambda - cold).lpNorm<Eigen::Infinity>(), 1e-4 * cold.lpNorm<Eigen::Infinity>());
}

TEST(ConstraintSolver, WarmSolvesFromTheKeptProductMatchAFreshSystemBitForBit) {
    // A system keeps A λ from one solve to the next and forms only the rows around each region
    // again; a system built anew multiplies every row. Hits one after another, a λ changed
    // between solves, and a solve with nothing to do must give the same bits either way.
    Lattice wall = jitteredBox(40, 10, 4);
    for (int t : tetsWithFaceOnPlane(wall.mesh(), {0, 1, 0}, -0.4, 1e-9)) wall.setFixed(t, true);
    const ConstraintSystem kept = wholeSystem(wall);
    Eigen::VectorXd q = gravityLoads(wall, kept);
    Eigen::VectorXd lambda;
    kept.solve(kept.rightHandSide(q, Eigen::Vector3d::Zero()), lambda, {});
    const std::vector<std::pair<int, Eigen::Vector3d>> hits = {
        {kept.particleCount() - 1, {2e3, -1e3, -4e3}}, {kept.particleCount() / 2, {-3e3, 2e3, 1e3}},
        {kept.particleCount() / 2, {0, 0, 0}}, {kept.particleCount() - 7, {1e3, 1e3, 1e3}}};
    for (size_t h = 0; h < hits.size(); ++h) {
        q.segment<3>(3 * hits[h].first) += hits[h].second;
        if (h == 3) lambda[5] += 1.0; // changed outside a solve: the kept product is not of it
        const Eigen::VectorXd b = kept.rightHandSide(q, Eigen::Vector3d::Zero());
        Eigen::VectorXd viaFresh = lambda;
        const SolveResult fromKept = kept.solve(b, lambda, {});
        const SolveResult fromFresh = wholeSystem(wall).solve(b, viaFresh, {});
        ASSERT_TRUE(fromKept.converged) << h;
        if (h == 0) {
            EXPECT_LT(fromKept.rowsSolved, kept.rowCount() / 3); // a region, not every row
        }
        EXPECT_EQ(fromKept.iterations, fromFresh.iterations) << h;
        EXPECT_EQ(fromKept.rowsSolved, fromFresh.rowsSolved) << h;
        EXPECT_EQ(fromKept.residual, fromFresh.residual) << h;
        EXPECT_EQ(lambda, viaFresh) << h;
    }
}

TEST(ConstraintSolver, APieceCutFromAnotherStartsFromItsForcesLinkByLink) {
    Lattice wall = jitteredBox();
    for (int t : tetsWithFaceOnPlane(wall.mesh(), {0, 1, 0}, -0.4, 1e-9)) wall.setFixed(t, true);
    LatticePiece whole = makePiece(wall, allParticles(wall));
    const ConstraintSystem& system = whole.constraintSystem(wall);
    system.solve(system.rightHandSide(gravityLoads(wall, system), Eigen::Vector3d::Zero()), whole.lambda, {});
    std::unordered_map<int, double> byLink;
    for (int k = 0; k < system.rowCount(); ++k) byLink[system.links()[k]] = whole.lambda[k];
    const int wholeRows = system.rowCount(); // inheritSolver takes (and frees) whole's system
    // The rest after the last ten tets came off.
    std::vector<int> rest = allParticles(wall);
    rest.resize(rest.size() - 10);
    LatticePiece part = makePiece(wall, rest);
    part.inheritSolver(whole, wall);
    ASSERT_TRUE(part.system);
    ASSERT_EQ(part.lambda.size(), part.system->rowCount());
    ASSERT_LT(part.system->rowCount(), wholeRows);
    for (int k = 0; k < part.system->rowCount(); ++k) EXPECT_EQ(part.lambda[k], byLink.at(part.system->links()[k]));
}

TEST(ConstraintSolver, KeptRightHandSideEqualsAFreshOneBitForBit) {
    // The kept b after loads change at a few particles, after a new spin, after the rows lose
    // broken links (same particles: the kept b is compacted) and after particles leave (it is
    // formed anew): each time the same bits as rightHandSide.
    Lattice wall = jitteredBox();
    for (int t : tetsWithFaceOnPlane(wall.mesh(), {0, 1, 0}, -0.4, 1e-9)) wall.setFixed(t, true);
    ConstraintSystem system = wholeSystem(wall);
    Eigen::VectorXd q = gravityLoads(wall, system);
    Eigen::Vector3d omega = Eigen::Vector3d::Zero();
    auto expectFresh = [&](const char* when) {
        EXPECT_EQ(system.keptRightHandSide(q, omega), system.rightHandSide(q, omega)) << when;
    };
    expectFresh("first");
    q.segment<3>(6) += Eigen::Vector3d(3e3, 1e3, -5e3);
    q[3 * (system.particleCount() - 1)] = -0.0; // a sign of zero is a change
    expectFresh("loads changed at two particles");
    expectFresh("nothing changed");
    omega = Eigen::Vector3d(0.3, -1.0, 2.0);
    expectFresh("new spin");
    q.segment<3>(0) *= 2.0;
    expectFresh("spin kept, loads changed");
    Eigen::VectorXd lambda = Eigen::VectorXd::Zero(system.rowCount());
    for (int k = 0; k < wall.linkCount(); k += 5) wall.breakLink(k);
    system.restrictTo(wall, allParticles(wall), lambda);
    expectFresh("rows of broken links dropped");
    q.segment<3>(9) += Eigen::Vector3d(-1e3, 2e3, 0.5);
    expectFresh("loads changed after the rows were dropped");
    std::vector<int> part = allParticles(wall);
    part.resize(part.size() / 2);
    system.restrictTo(wall, part, lambda);
    q = gravityLoads(wall, system);
    expectFresh("particles left");
}

TEST(ConstraintSolver, ARestrictedSystemSolvesRegionsAsAFreshOneBitForBit) {
    // restrictTo filters its rows-per-particle index in place; the regions a warm solve grows
    // walk that index, in its order. Two restrictions (breaks, then a part with particles gone
    // at the start, middle and end), then hits near a few particles: the same regions, iterations
    // and λ as a system built anew.
    Lattice wall = jitteredBox(40, 10, 4);
    for (int t : tetsWithFaceOnPlane(wall.mesh(), {0, 1, 0}, -0.4, 1e-9)) wall.setFixed(t, true);
    ConstraintSystem system = wholeSystem(wall);
    Eigen::VectorXd lambda;
    system.solve(system.rightHandSide(gravityLoads(wall, system), Eigen::Vector3d::Zero()), lambda, {});
    for (int k = 3; k < wall.linkCount(); k += 11) wall.breakLink(k);
    system.restrictTo(wall, allParticles(wall), lambda);
    std::vector<int> part;
    for (int p = 2; p < wall.particleCount() - 5; ++p)
        if (p % 5 != 3 && (p < 4000 || p > 4300)) part.push_back(p);
    for (int k = 5; k < wall.linkCount(); k += 13) wall.breakLink(k);
    system.restrictTo(wall, part, lambda);
    const ConstraintSystem fresh(wall, part, allLinks(wall));
    ASSERT_EQ(system.links(), fresh.links());
    Eigen::VectorXd q = gravityLoads(wall, fresh);
    // (-1: the rest after the breaks first, a solve over every row.)
    for (int hit : {-1, fresh.particleCount() - 1, fresh.particleCount() / 2}) {
        if (hit >= 0) q.segment<3>(3 * hit) += Eigen::Vector3d(2e3, -1e3, -4e3);
        const Eigen::VectorXd b = fresh.rightHandSide(q, Eigen::Vector3d::Zero());
        Eigen::VectorXd viaFresh = lambda;
        const SolveResult restricted = system.solve(b, lambda, {});
        const SolveResult built = fresh.solve(b, viaFresh, {});
        if (hit >= 0) {
            EXPECT_LT(built.rowsSolved, fresh.rowCount() / 2) << hit; // regions, not every row
        }
        EXPECT_EQ(restricted.rowsSolved, built.rowsSolved) << hit;
        EXPECT_EQ(restricted.iterations, built.iterations) << hit;
        EXPECT_EQ(lambda, viaFresh) << hit;
    }
}

TEST(ConstraintSolver, RestrictingLeavesTheSystemBuiltWithoutTheBrokenLinksAndTheParticlesLeft) {
    Lattice wall = jitteredBox();
    for (int t : tetsWithFaceOnPlane(wall.mesh(), {0, 1, 0}, -0.4, 1e-9)) wall.setFixed(t, true);
    // The same piece after breaks, and a part of it (every third particle gone).
    std::vector<int> part;
    for (int p = 0; p < wall.particleCount(); ++p)
        if (p % 3 != 1) part.push_back(p);
    for (const std::vector<int>& particles : {allParticles(wall), part}) {
        ConstraintSystem system = wholeSystem(wall);
        const Eigen::VectorXd q = gravityLoads(wall, system);
        Eigen::VectorXd lambda;
        system.solve(system.rightHandSide(q, Eigen::Vector3d::Zero()), lambda, {});
        const Eigen::VectorXd before = lambda;
        const std::vector<int> rows = system.links();
        for (int k = 0; k < wall.linkCount(); k += 7) wall.breakLink(k);
        ASSERT_TRUE(system.canRestrictTo(wall, particles));
        system.restrictTo(wall, particles, lambda);
        const ConstraintSystem fresh(wall, particles, test::indices(wall.linkCount()));
        ASSERT_EQ(system.particles(), fresh.particles());
        ASSERT_EQ(system.links(), fresh.links());
        ASSERT_EQ(lambda.size(), fresh.rowCount());
        for (int k = 0, j = 0; k < fresh.rowCount(); ++k) {
            while (rows[size_t(j)] != fresh.links()[k]) ++j;
            EXPECT_EQ(lambda[k], before[j]); // each kept row keeps its λ
        }
        // The same matrix: the same products.
        const Eigen::VectorXd x = Eigen::VectorXd::LinSpaced(fresh.rowCount(), -1.0, 2.0);
        Eigen::VectorXd a, b;
        system.multiply(x, a);
        fresh.multiply(x, b);
        EXPECT_EQ(a, b);
        const Eigen::VectorXd qPart = gravityLoads(wall, fresh);
        const Eigen::Vector3d omega(0.3, -1.0, 2.0);
        EXPECT_EQ(system.rightHandSide(qPart, omega), fresh.rightHandSide(qPart, omega));
        // The same proofs (they scale each row by its diagonal, kept through the restriction):
        // after a hit, a warm solve that stops once the exact λ is proven within 3 or 15
        // times its largest force (which takes a few iterations here) stops at the same iteration
        // with the same λ.
        Eigen::VectorXd hit = qPart;
        hit.segment<3>(3 * (fresh.particleCount() / 2)) += Eigen::Vector3d(3e3, 1e3, -5e3);
        const Eigen::VectorXd rhs = fresh.rightHandSide(hit, Eigen::Vector3d::Zero());
        Eigen::VectorXd exact;
        fresh.solve(rhs, exact, {});
        SafeRange safe;
        safe.eigenvalueBound = scaledEigenvalueLowerBound(fresh);
        ASSERT_GT(safe.eigenvalueBound, 0.0);
        const double width = 3.0 * exact.cwiseAbs().maxCoeff();
        for (int k = 0; k < fresh.rowCount(); ++k) {
            const double w = width * (k % 2 ? 1.0 : 5.0); // uneven, so that each row's diagonal counts
            safe.lower.push_back(exact[k] - w), safe.upper.push_back(exact[k] + w);
        }
        Eigen::VectorXd viaRestricted = lambda, viaFresh = lambda;
        const SolveResult restricted = system.solve(rhs, viaRestricted, {}, &safe);
        const SolveResult built = fresh.solve(rhs, viaFresh, {}, &safe);
        EXPECT_TRUE(built.provenSafe);
        EXPECT_GT(built.iterations, 0);
        EXPECT_EQ(restricted.provenSafe, built.provenSafe);
        EXPECT_EQ(restricted.iterations, built.iterations);
        EXPECT_EQ(viaRestricted, viaFresh);
        // Links joined again (every 7th broke above; a few joined twice): their rows go in, in
        // link order with λ = 0, and the system is again the one built anew.
        for (int k = 0; k < wall.linkCount(); k += 7) wall.joinLink(k);
        for (int k = 0; k < wall.linkCount(); k += 14) wall.breakLink(k), wall.joinLink(k);
        for (int k = 1; k < wall.linkCount(); k += 7) wall.breakLink(k), wall.joinLink(k); // rows kept
        ASSERT_TRUE(system.canRestrictTo(wall, particles));
        const Eigen::VectorXd solved = viaFresh;
        Eigen::VectorXd joinedLambda = viaFresh;
        system.restrictTo(wall, particles, joinedLambda);
        const ConstraintSystem rejoined(wall, particles, test::indices(wall.linkCount()));
        ASSERT_EQ(system.links(), rejoined.links());
        ASSERT_GT(rejoined.rowCount(), fresh.rowCount());
        ASSERT_EQ(joinedLambda.size(), rejoined.rowCount());
        for (int k = 0, j = 0; k < rejoined.rowCount(); ++k) {
            const bool old = j < fresh.rowCount() && fresh.links()[j] == rejoined.links()[k];
            EXPECT_EQ(joinedLambda[k], old ? solved[j++] : 0.0);
        }
        const Eigen::VectorXd y = Eigen::VectorXd::LinSpaced(rejoined.rowCount(), -1.0, 2.0);
        system.multiply(y, a);
        rejoined.multiply(y, b);
        EXPECT_EQ(a, b);
        EXPECT_EQ(system.keptRightHandSide(hit, omega), rejoined.rightHandSide(hit, omega));
        EXPECT_EQ(system.assemble().toDense(), rejoined.assemble().toDense());
        // A system whose rows are not in link order cannot take the joined links' rows.
        std::vector<int> backwards = test::indices(wall.linkCount());
        std::reverse(backwards.begin(), backwards.end());
        ConstraintSystem unordered(wall, allParticles(wall), backwards);
        wall.breakLink(3), wall.joinLink(3);
        EXPECT_FALSE(unordered.canRestrictTo(wall, particles));
        // Asked anyway, it refuses before changing anything: the system still multiplies as before.
        const Eigen::VectorXd probe = Eigen::VectorXd::LinSpaced(unordered.rowCount(), -1.0, 2.0);
        Eigen::VectorXd productBefore, productAfter, unorderedLambda = Eigen::VectorXd::Zero(unordered.rowCount());
        unordered.multiply(probe, productBefore);
        EXPECT_THROW(unordered.restrictTo(wall, particles, unorderedLambda), shatter::InputError);
        ASSERT_EQ(unordered.rowCount(), probe.size());
        unordered.multiply(probe, productAfter);
        EXPECT_EQ(productBefore, productAfter);
        // Nor to particles it does not hold (the part's third particles are gone): an error,
        // where the merge walk would have stalled and dropped the rows after the first of them.
        if (particles.size() < size_t(wall.particleCount())) {
            EXPECT_THROW(system.restrictTo(wall, allParticles(wall), lambda), shatter::InputError);
        }
    }
}

} // namespace
} // namespace shatter::lattice
