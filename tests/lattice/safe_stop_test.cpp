// A solve that stops once nothing can break (EigenvalueBound.h, SafeRange): the bound is a
// lower bound, the stop never fires when the exact forces leave the range, and an analysis
// that uses it breaks and weakens exactly what one solving to the tolerance does. The same for
// the stop once the links that break are decided (SafeRange::breakLower/breakUpper).
#include "LatticeFixtures.h"
#include <shatter/plugin/lattice/EigenvalueBound.h>
#include <shatter/plugin/lattice/FractureAnalysis.h>
#include <shatter/plugin/lattice/TetGenerators.h>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <random>

namespace shatter::lattice {
namespace {

Lattice standingBox(int nx, int ny, int nz) {
    GeneratorOptions o;
    o.jitter = 0.2;
    o.seed = 3;
    Lattice box(tetBox({1.2, 0.8, 0.6}, {nx, ny, nz}, o), adobe());
    for (int t : tetsWithFaceOnPlane(box.mesh(), {0, 1, 0}, -0.4, 1e-9)) box.setFixed(t, true);
    return box;
}

double smallestScaledEigenvalue(const ConstraintSystem& system) {
    const Eigen::MatrixXd a(system.assemble());
    const Eigen::VectorXd s = a.diagonal().cwiseSqrt().cwiseInverse();
    return Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(s.asDiagonal() * a * s.asDiagonal()).eigenvalues()[0];
}

TEST(EigenvalueBound, BelowTheSmallestEigenvalueAndWithinAFactorOfTwoOfIt) {
    Lattice box = standingBox(6, 4, 3);
    const ConstraintSystem whole(box, test::indices(box.particleCount()), test::indices(box.linkCount()));
    const double bound = scaledEigenvalueLowerBound(whole), exact = smallestScaledEigenvalue(whole);
    EXPECT_GT(bound, 0.45 * exact); // halving steps, 0.9 kept
    EXPECT_LE(bound, exact);
    // Interlacing: after breaks, and for a part of the body, the bound still holds.
    for (int k = 0; k < box.linkCount(); k += 3) box.breakLink(k);
    const ConstraintSystem broken(box, test::indices(box.particleCount()), test::indices(box.linkCount()));
    EXPECT_LE(bound, smallestScaledEigenvalue(broken));
    const ConstraintSystem part(box, test::indices(box.particleCount() / 2), test::indices(box.linkCount()));
    EXPECT_LE(bound, smallestScaledEigenvalue(part));
}

TEST(EigenvalueBound, NoneWhenLinksAreRedundant) {
    // A tet whose four neighbours are fixed: four links on three degrees of freedom.
    Lattice star(test::starOfFive(), concrete());
    for (int i = 1; i < 5; ++i) star.setFixed(i, true);
    EXPECT_EQ(scaledEigenvalueLowerBound(ConstraintSystem(star, test::indices(5), test::indices(4))), 0.0);
}

TEST(SafeStop, NeverWhenTheExactForcesLeaveTheRangeAndEarlierWhenTheyStayInside) {
    const Lattice box = standingBox(8, 6, 3);
    const ConstraintSystem system(box, test::indices(box.particleCount()), test::indices(box.linkCount()));
    Eigen::VectorXd q = Eigen::VectorXd::Zero(3 * system.particleCount());
    for (int i = 0; i < system.particleCount(); ++i) q[3 * i + 1] = -9.81 * box.particles()[i].mass;
    const Eigen::VectorXd rest = system.rightHandSide(q, Eigen::Vector3d::Zero());
    q.segment<3>(3 * (system.particleCount() / 2)) += Eigen::Vector3d(3e3, 1e3, -5e3); // an impact
    const Eigen::VectorXd b = system.rightHandSide(q, Eigen::Vector3d::Zero());
    const Eigen::VectorXd exact = Eigen::MatrixXd(system.assemble()).ldlt().solve(b);
    ConstraintSolverSettings tight;
    tight.tolerance = 1e-12;
    Eigen::VectorXd atRest;
    system.solve(rest, atRest, tight);
    const int n = system.rowCount();
    const double scale = exact.cwiseAbs().maxCoeff();
    Eigen::VectorXd full = atRest;
    const int fullIterations = system.solve(b, full, {}).iterations;

    SafeRange safe;
    safe.eigenvalueBound = scaledEigenvalueLowerBound(system);
    ASSERT_GT(safe.eigenvalueBound, 0.0);
    std::mt19937 random(7);
    std::uniform_real_distribution<double> room(0.5, 1.0);
    int stoppedEarly = 0;
    for (double width : {1e-2, 0.1, 1.0, 4.0, 16.0}) {
        for (int outside = -1; outside < n; outside += std::max(1, n / 7)) {
            // Every row's range holds its exact force with room of 0.5-1 × `width` × the largest
            // force; row `outside` (when >= 0) has the exact force just past one end.
            safe.lower.assign(size_t(n), 0.0);
            safe.upper.assign(size_t(n), 0.0);
            for (int k = 0; k < n; ++k) {
                safe.lower[size_t(k)] = exact[k] - width * scale * room(random);
                safe.upper[size_t(k)] = exact[k] + width * scale * room(random);
            }
            // Started from the forces at rest, and from forces near the exact ones (inside the
            // range on every row, so only the bound can tell that row `outside` ends outside).
            Eigen::VectorXd near = exact;
            for (int k = 0; k < n; ++k) near[k] += 1e-4 * scale * (2.0 * room(random) - 1.5);
            if (outside >= 0) {
                const double side = outside % 2 ? 1.0 : -1.0; // past the upper or the lower end
                (side > 0 ? safe.upper : safe.lower)[size_t(outside)] = exact[outside] - side * 1e-9 * scale;
                near[outside] = exact[outside] - side * 1e-4 * scale;
            }
            for (const Eigen::VectorXd& start : {atRest, near}) {
                Eigen::VectorXd lambda = start;
                const SolveResult r = system.solve(b, lambda, {}, &safe);
                EXPECT_TRUE(r.converged);
                if (outside >= 0) {
                    EXPECT_FALSE(r.provenSafe) << "width " << width << ", row " << outside;
                }
                if (!r.provenSafe) continue;
                for (int k = 0; k < n; ++k) {
                    EXPECT_GT(lambda[k], safe.lower[size_t(k)]);
                    EXPECT_LT(lambda[k], safe.upper[size_t(k)]);
                }
                stoppedEarly += r.iterations > 0 && r.iterations < fullIterations;
            }
        }
    }
    // The widest ranges are proven by CG with fewer iterations than the tolerance needs.
    EXPECT_GE(stoppedEarly, 2);
}

TEST(SafeStop, DecidesTheBreaksOnlyWhenEveryRowIsOnTheSideOfItsExactForce) {
    const Lattice box = standingBox(8, 6, 3);
    const ConstraintSystem system(box, test::indices(box.particleCount()), test::indices(box.linkCount()));
    Eigen::VectorXd q = Eigen::VectorXd::Zero(3 * system.particleCount());
    for (int i = 0; i < system.particleCount(); ++i) q[3 * i + 1] = -9.81 * box.particles()[i].mass;
    q.segment<3>(3 * (system.particleCount() / 2)) += Eigen::Vector3d(3e3, 1e3, -5e3); // an impact
    const Eigen::VectorXd b = system.rightHandSide(q, Eigen::Vector3d::Zero());
    const Eigen::VectorXd exact = Eigen::MatrixXd(system.assemble()).ldlt().solve(b);
    const int n = system.rowCount();
    const double scale = exact.cwiseAbs().maxCoeff();
    Eigen::VectorXd full;
    const int fullIterations = system.solve(b, full, {}).iterations;

    SafeRange safe;
    safe.eigenvalueBound = scaledEigenvalueLowerBound(system);
    ASSERT_GT(safe.eigenvalueBound, 0.0);
    safe.lower.assign(size_t(n), 0.0); // an empty safe range: only the breaks can stop a solve
    safe.upper.assign(size_t(n), 0.0);
    std::mt19937 random(11);
    std::uniform_real_distribution<double> room(0.5, 1.0);
    auto beyond = [&](const Eigen::VectorXd& lambda, int k) {
        return lambda[k] < safe.breakLower[size_t(k)] || lambda[k] > safe.breakUpper[size_t(k)];
    };
    int decided = 0;
    for (double width : {1e-2, 0.1, 1.0, 4.0}) {
        for (int tricky = -1; tricky < n; tricky += std::max(1, n / 7)) {
            // Every fifth row's exact force lies beyond its break range, the others' inside it,
            // with room of 0.5-1 × `width` × the largest force; row `tricky` (when >= 0) has it
            // just past one end while the start is on the other side.
            safe.breakLower.assign(size_t(n), 0.0);
            safe.breakUpper.assign(size_t(n), 0.0);
            for (int k = 0; k < n; ++k) {
                const double margin = width * scale * room(random);
                if (k % 5 != 0) {
                    safe.breakLower[size_t(k)] = exact[k] - margin;
                    safe.breakUpper[size_t(k)] = exact[k] + width * scale * room(random);
                } else if (k % 2) {
                    safe.breakLower[size_t(k)] = exact[k] - 3.0 * margin;
                    safe.breakUpper[size_t(k)] = exact[k] - margin;
                } else {
                    safe.breakLower[size_t(k)] = exact[k] + margin;
                    safe.breakUpper[size_t(k)] = exact[k] + 3.0 * margin;
                }
            }
            Eigen::VectorXd near = exact;
            for (int k = 0; k < n; ++k) near[k] += 1e-4 * scale * (2.0 * room(random) - 1.5);
            if (tricky >= 0) {
                safe.breakLower[size_t(tricky)] = exact[tricky] - 3.0 * width * scale; // below `near`
                safe.breakUpper[size_t(tricky)] = exact[tricky] - 1e-9 * scale;       // just beyond
                near[tricky] = exact[tricky] - 0.3 * width * scale;                // inside
            }
            for (const Eigen::VectorXd& start : {Eigen::VectorXd(), near}) {
                Eigen::VectorXd lambda = start;
                const SolveResult r = system.solve(b, lambda, {}, &safe);
                EXPECT_TRUE(r.converged);
                EXPECT_FALSE(r.provenSafe);
                if (!r.breaksDecided) continue;
                for (int k = 0; k < n; ++k) EXPECT_EQ(beyond(lambda, k), beyond(exact, k)) << "row " << k;
                decided += r.iterations > 0 && r.iterations < fullIterations;
            }
        }
    }
    // The wide ranges are decided by CG with fewer iterations than the tolerance needs.
    EXPECT_GE(decided, 2);
}

// A warm solve after a hit at one corner of a long box solves a region around it; the region's
// CG confirms the decided breaks on its own, with the rows outside it and its boundary counted
// from before, and refuses while a row outside it would break differently at the exact forces.
TEST(SafeStop, ARegionDecidesTheBreaksOnlyWhenTheRowsOutsideItAreDecidedToo) {
    const Lattice box = standingBox(24, 6, 3);
    const ConstraintSystem system(box, test::indices(box.particleCount()), test::indices(box.linkCount()));
    const int n = system.rowCount();
    Eigen::VectorXd q = Eigen::VectorXd::Zero(3 * system.particleCount());
    for (int i = 0; i < system.particleCount(); ++i) q[3 * i + 1] = -9.81 * box.particles()[i].mass;
    ConstraintSolverSettings tight;
    tight.tolerance = 1e-12;
    Eigen::VectorXd rest; // the warm start: the forces at rest, as in a running scene
    ASSERT_TRUE(system.solve(system.rightHandSide(q, Eigen::Vector3d::Zero()), rest, tight).converged);
    auto corner = [&](int i) { return box.particles()[size_t(i)].position.dot(Eigen::Vector3d(1, 1, 1)); };
    int hit = 0, far = 0;
    for (int i = 0; i < system.particleCount(); ++i) {
        if (corner(i) > corner(hit)) hit = i;
        if (corner(i) < corner(far) && box.inverseMass(i) > 0.0) far = i;
    }
    q.segment<3>(3 * hit) += Eigen::Vector3d(3e3, -1e3, -2e3);
    const Eigen::VectorXd b = system.rightHandSide(q, Eigen::Vector3d::Zero());
    Eigen::VectorXd exact;
    ASSERT_TRUE(system.solve(b, exact, tight).converged);
    Eigen::VectorXd plain = rest;
    const SolveResult toTolerance = system.solve(b, plain, {});
    ASSERT_LT(toTolerance.rowsSolved, n / 2); // the warm solve is local

    SafeRange safe;
    safe.eigenvalueBound = scaledEigenvalueLowerBound(system);
    ASSERT_GT(safe.eigenvalueBound, 0.0);
    safe.lower.assign(size_t(n), 0.0); // an empty safe range: only the breaks can stop a solve
    safe.upper.assign(size_t(n), 0.0);
    // The rows the hit loads most break (their exact force beyond the range by `width` × the
    // largest change of force), the others hold with that room.
    const double change = (exact - rest).cwiseAbs().maxCoeff();
    const double width = 0.3 * change;
    safe.breakLower.resize(size_t(n));
    safe.breakUpper.resize(size_t(n));
    for (int k = 0; k < n; ++k) {
        const bool breaks = std::abs(exact[k] - rest[k]) > 0.5 * change;
        safe.breakLower[size_t(k)] = exact[k] - width;
        safe.breakUpper[size_t(k)] = breaks ? exact[k] - 0.5 * width : exact[k] + width;
    }
    auto beyond = [&](const Eigen::VectorXd& lambda, int k) {
        return lambda[k] < safe.breakLower[size_t(k)] || lambda[k] > safe.breakUpper[size_t(k)];
    };
    Eigen::VectorXd lambda = rest;
    const SolveResult decided = system.solve(b, lambda, {}, &safe);
    EXPECT_TRUE(decided.breaksDecided);
    EXPECT_LT(decided.rowsSolved, n / 2); // by a region's CG
    EXPECT_LT(decided.iterations, toTolerance.iterations);
    // The residual the proof summed (the region's, its boundary's, the rest's) is the true one.
    Eigen::VectorXd product;
    system.multiply(lambda, product);
    const double residual = (b - product).norm() / b.norm();
    EXPECT_NEAR(decided.residual, residual, 1e-9 * residual);
    for (int k = 0; k < n; ++k) EXPECT_EQ(beyond(lambda, k), beyond(exact, k)) << "row " << k;

    // A row at the far corner, outside every region, whose exact force crosses its break range's
    // end between the warm start and the exact forces: the region alone must not decide.
    int row = -1;
    for (int k = 0; k < n; ++k) {
        const Link& l = box.links()[size_t(system.links()[size_t(k)])];
        if ((l.a == far || l.b == far) && (row < 0 || std::abs(exact[k] - rest[k]) > std::abs(exact[row] - rest[row])))
            row = k;
    }
    ASSERT_GE(row, 0);
    const double crossing = exact[row] - rest[row];
    ASSERT_NE(crossing, 0.0);
    safe.breakLower[size_t(row)] = std::min(rest[row], exact[row]) - width;
    safe.breakUpper[size_t(row)] = 0.5 * (rest[row] + exact[row]); // exact beyond iff it grew
    lambda = rest;
    const SolveResult refused = system.solve(b, lambda, {}, &safe);
    EXPECT_TRUE(refused.converged);
    if (refused.breaksDecided) {
        for (int k = 0; k < n; ++k) EXPECT_EQ(beyond(lambda, k), beyond(exact, k)) << "row " << k;
    }
    EXPECT_NE(beyond(rest, row), beyond(exact, row)); // the warm start is on the wrong side
}

// A bar fixed at one end and pulled at the other (as Breaking's PullTest), with or without the
// bound that lets its solves stop early.
struct Bar {
    Lattice lattice;
    LatticePiece piece;
    Eigen::VectorXd loads;
    Bar(double force, bool safeStop)
        : lattice(tetBox({1.0, 0.1, 0.1}, {20, 2, 2}), [] {
              MaterialSettings m = glass();
              m.strength = 6e5;
              return m;
          }()) {
        for (int t : tetsWithFaceOnPlane(lattice.mesh(), {1, 0, 0}, -0.5, 1e-9)) lattice.setFixed(t, true);
        piece = makePiece(lattice, test::indices(lattice.particleCount()));
        if (!safeStop) piece.eigenvalueBound = 0.0;
        loads = Eigen::VectorXd::Zero(3 * lattice.particleCount());
        const auto end = tetsWithFaceOnPlane(lattice.mesh(), {1, 0, 0}, 0.5, 1e-9);
        for (int t : end) loads[3 * t] = force / double(end.size());
    }
    FractureReport analyse(double fraction, const FractureAnalysisSettings& s) {
        Random random(1);
        return analyseFracture(lattice, piece, fraction * loads, Eigen::Vector3d::Zero(), s, random);
    }
};

TEST(SafeStop, BreaksAndWeakensWhatTheFullSolveDoesJustBelowAndAboveEachThreshold) {
    FractureAnalysisSettings s;
    s.spreading.enabled = false;
    // The pull at which the most loaded link reaches its capacity.
    Bar probe(1e4, false);
    s.breaking.weakenByLoad = false;
    const double atCapacity = 1e4 / probe.analyse(1.0, s).maxUtilisation;
    int provenSafe = 0, breaksDecided = 0;
    for (bool weaken : {false, true}) {
        s.breaking.weakenByLoad = weaken;
        const double threshold = weaken ? s.breaking.weakeningOnset : 1.0;
        for (double f : {0.2, 0.9, 0.99, 0.999, 1.001, 1.01, 1.1}) {
            Bar withStop(f * threshold * atCapacity, true), without(f * threshold * atCapacity, false);
            ASSERT_GT(withStop.piece.eigenvalueBound, 0.0);
            // A lighter load first, so the second analysis starts warm as in a running scene.
            for (double fraction : {0.5, 1.0}) {
                const FractureReport a = withStop.analyse(fraction, s), b = without.analyse(fraction, s);
                provenSafe += a.provenSafe;
                breaksDecided += a.breaksDecided;
                EXPECT_EQ(b.provenSafe, 0);
                EXPECT_EQ(a.broken, b.broken) << "load " << f << " x threshold " << threshold;
                for (int k = 0; k < withStop.lattice.linkCount(); ++k) {
                    const Link &la = withStop.lattice.links()[k], &lb = without.lattice.links()[k];
                    EXPECT_EQ(la.broken, lb.broken);
                    EXPECT_EQ(la.strength < la.baseStrength, lb.strength < lb.baseStrength) << "link " << k;
                    EXPECT_NEAR(la.strength, lb.strength, 1e-5 * lb.baseStrength);
                }
            }
            // Above the threshold something broke (or weakened), below it nothing did.
            int weakened = 0;
            for (const Link& l : withStop.lattice.links()) weakened += l.strength < l.baseStrength;
            EXPECT_EQ(f > 1.0, (weaken ? weakened : withStop.lattice.brokenCount()) > 0) << "load " << f;
        }
    }
    EXPECT_GT(provenSafe, 0); // the stop did fire on the light loads
    EXPECT_GT(breaksDecided, 0); // and so did the one for the breaks, on the heavy ones
}

// The piece keeps its safe range from one analysis to the next and forms it again only at rows
// whose strength changed (LatticePiece::RowBuffers): a sequence of analyses that weaken links,
// break some (the system loses rows) and rest gives bit for bit the λ, breaks and strengths of
// the same sequence with the buffers dropped before every analysis, and the kept range equals
// the one formed afresh.
TEST(SafeStop, AKeptSafeRangeGivesWhatOneFormedAfreshGives) {
    FractureAnalysisSettings s;
    s.spreading.enabled = false;
    Bar probe(1e4, false);
    const double atCapacity = 1e4 / probe.analyse(1.0, s).maxUtilisation;
    Bar kept(atCapacity, true), fresh(atCapacity, true);
    int brokeAt = -1, weakened = 0; // weakened: most links weakened but unbroken after an analysis
    const std::vector<double> fractions = {0.3, 0.6, 0.6, 0.8, 0.95, 1.05, 1.05, 0.4, 0.4, 1.3, 0.2};
    for (size_t i = 0; i < fractions.size(); ++i) {
        fresh.piece.rows = {};
        const FractureReport a = kept.analyse(fractions[i], s), b = fresh.analyse(fractions[i], s);
        EXPECT_EQ(a.broken, b.broken) << "analysis " << i;
        EXPECT_EQ(a.provenSafe, b.provenSafe);
        EXPECT_EQ(a.breaksDecided, b.breaksDecided);
        ASSERT_EQ(kept.piece.lambda.size(), fresh.piece.lambda.size());
        for (Eigen::Index k = 0; k < kept.piece.lambda.size(); ++k)
            ASSERT_EQ(std::bit_cast<uint64_t>(kept.piece.lambda[k]), std::bit_cast<uint64_t>(fresh.piece.lambda[k]));
        for (int k = 0; k < kept.lattice.linkCount(); ++k)
            ASSERT_EQ(kept.lattice.links()[k].strength, fresh.lattice.links()[k].strength) << "link " << k;
        const SafeRange &x = kept.piece.rows.safe, &y = fresh.piece.rows.safe;
        EXPECT_EQ(x.lower, y.lower);
        EXPECT_EQ(x.upper, y.upper);
        EXPECT_EQ(x.breakLower, y.breakLower);
        EXPECT_EQ(x.breakUpper, y.breakUpper);
        if (brokeAt < 0 && !a.broken.empty()) brokeAt = int(i);
        int now = 0;
        for (const Link& l : kept.lattice.links()) now += !l.broken && l.strength < l.baseStrength;
        weakened = std::max(weakened, now);
    }
    EXPECT_GE(brokeAt, 0); // links broke (rows dropped) and analyses ran after it
    EXPECT_LT(brokeAt, int(fractions.size()) - 1);
    EXPECT_GT(weakened, 0); // and strengths changed without a break
}

} // namespace
} // namespace shatter::lattice
