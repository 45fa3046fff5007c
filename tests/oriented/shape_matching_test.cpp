// Generalized shape matching (source 000 §3.2.1, §3.2.3) and primitive deformation (§3.3).
#include "OrientedFixtures.h"
#include <shatter/plugin/common/InputError.h>
#include <shatter/plugin/oriented/PrimitiveDeformation.h>
#include <shatter/plugin/oriented/RotationExtraction.h>

#include <cstring>
#include <gtest/gtest.h>

namespace shatter::oriented {
namespace {

using test::cubeBlock;

// Poses every particle by x = R x̄ + t, q = R (a rigid motion of the rest shape).
void moveRigidly(OrientedParticles& p, const Eigen::Quaterniond& R, const Eigen::Vector3d& t) {
    for (int i = 0; i < p.size(); ++i) {
        p.position[i] = R * p.restPosition[i] + t;
        p.orientation[i] = R;
    }
}

void projectAll(OrientedSolver& s, double stiffness = 1.0) {
    auto& p = s.particles();
    s.groups().refreshMoments(p, p.orientation);
    for (int g = 0; g < s.groups().size(); ++g) s.groups().project(g, p, p.position, p.orientation, stiffness, 20);
}

TEST(ShapeMatching, ASweepsBatchesHoldEveryGroupOnceAndShareNoParticle) {
    // Groups of a batch are projected as one (their fits interleaved): that is one after the
    // other only if they share no particle. A sheet-like slab (groups three apart along a row
    // share nothing: every batch full) and a 5 × 5 × 5 block (groups of 3 × 3 × 3: at most 8
    // share nothing, and the window finds 2 to 4).
    struct Case {
        test::CubeBlock block;
        int mostBatches;
    };
    for (const Case& c : {Case{cubeBlock(30, 1, 20, 0.1), 600 / kRotationLanes}, Case{cubeBlock(5, 5, 5, 0.1), 125 / 2}}) {
        const auto solver = test::blockSolver(c.block);
        const ShapeMatchingGroups& groups = solver.groups();
        std::vector<int> seen(size_t(groups.size()), 0);
        for (int b = 0; b < groups.batches(); ++b) {
            const auto batch = groups.batch(b);
            ASSERT_GE(batch.size(), 1u);
            ASSERT_LE(batch.size(), size_t(kRotationLanes));
            std::vector<int> holders(size_t(groups.size()), 0);
            for (int g : batch) {
                ++seen[size_t(g)];
                for (int j : groups.members(g)) EXPECT_EQ(++holders[size_t(j)], 1) << "batch " << b << " particle " << j;
            }
        }
        for (int g = 0; g < groups.size(); ++g) EXPECT_EQ(seen[size_t(g)], 1) << "group " << g;
        EXPECT_LE(groups.batches(), c.mostBatches); // batches of several, or nothing overlaps
    }
}

TEST(ShapeMatching, ProjectingAllIsProjectingEachGroupInBatchOrderOnEveryPath) {
    // projectAll's batched fits give exactly what project() gives group by group in the
    // batches' order (bit for bit), from a deformed, turned block with a fixed particle, on
    // the portable path and on AVX2 (4-wide lanes) where the processor has it: the same bits.
    std::mt19937 rng(21);
    auto start = test::blockSolver(cubeBlock(6, 2, 5, 0.1));
    for (int i = 0; i < start.particles().size(); ++i) {
        start.particles().position[i] += test::randomVector(rng, 0.02);
        start.particles().orientation[i] = Eigen::Quaterniond(Eigen::AngleAxisd(0.2, test::randomVector(rng, 1).normalized()));
    }
    start.particles().fixed[7] = 1;
    auto single = start;
    auto& ps = single.particles();
    for (int sweep = 0; sweep < 3; ++sweep) {
        single.groups().refreshMoments(ps, ps.orientation);
        for (int b = 0; b < single.groups().batches(); ++b)
            for (int g : single.groups().batch(b)) single.groups().project(g, ps, ps.position, ps.orientation, 0.6, 2, 1e-3);
    }
    int paths = 0;
    for (const SimdPath path : {SimdPath::Portable, SimdPath::Avx2}) {
        if (!simdPathAvailable(path)) continue;
        ++paths;
        auto batched = start;
        auto& pb = batched.particles();
        for (int sweep = 0; sweep < 3; ++sweep) {
            batched.groups().refreshMoments(pb, pb.orientation);
            batched.groups().projectAll(pb, pb.position, pb.orientation, 0.6, 2, 1e-3, path);
        }
        for (int i = 0; i < pb.size(); ++i) {
            for (int e = 0; e < 3; ++e) EXPECT_EQ(pb.position[i][e], ps.position[i][e]) << i << " path " << int(path);
            for (int e = 0; e < 4; ++e)
                EXPECT_EQ(pb.orientation[i].coeffs()[e], ps.orientation[i].coeffs()[e]) << i << " path " << int(path);
        }
        EXPECT_EQ(pb.position[7], start.particles().position[7]); // fixed: not moved
    }
    if (paths < 2) GTEST_SKIP() << "no AVX2 here: only the portable path was compared";
}

// A 6×2×5 block with every particle jittered and turned (seeded): the start of the
// runs-of-sweeps tests.
OrientedSolver jitteredRunBlock(unsigned seed) {
    std::mt19937 rng(seed);
    auto start = test::blockSolver(cubeBlock(6, 2, 5, 0.1));
    for (int i = 0; i < start.particles().size(); ++i) {
        start.particles().position[i] += test::randomVector(rng, 0.02);
        start.particles().orientation[i] = Eigen::Quaterniond(Eigen::AngleAxisd(0.2, test::randomVector(rng, 1).normalized()));
    }
    return start;
}

// The particles a run's contacts touch (one listed twice), and how they move between sweeps:
// by a step that depends on where each is (a stale copy would give other bits).
const std::vector<int> touched{3, 17, 40, 17, 59};
void pushTouched(OrientedParticles& p) {
    for (int j : touched) p.position[j] += Eigen::Vector3d(0.01, -0.003, 0.002) + 0.1 * p.position[j];
}

TEST(ShapeMatching, ARunOfSweepsIsItsSweepsOneByOneOnEveryPath) {
    // projectAllInRun keeps the sweep's copy of the positions between the sweeps of a run and
    // copies only the touched particles out and in: with some particles moved between sweeps
    // (as contacts move them), the same bits as projectAll sweep by sweep. A touched particle
    // listed twice, and untouched ones, are checked too; x between sweeps is read only at the
    // touched ones (the rest are stale there, by contract).
    const auto start = jitteredRunBlock(23);
    int paths = 0;
    for (const SimdPath path : {SimdPath::Portable, SimdPath::Avx2}) {
        if (!simdPathAvailable(path)) continue;
        ++paths;
        auto bySweep = start, inRun = start;
        auto &pa = bySweep.particles(), &pb = inRun.particles();
        bySweep.groups().refreshMoments(pa, pa.orientation, path);
        inRun.groups().refreshMoments(pb, pb.orientation, path);
        for (int sweep = 0; sweep < 4; ++sweep) {
            bySweep.groups().projectAll(pa, pa.position, pa.orientation, 0.6, 2, 1e-3, path);
            inRun.groups().projectAllInRun(pb, pb.position, pb.orientation, 0.6, 2, 1e-3, path, sweep == 0, sweep == 3,
                                           touched);
            for (int j : touched)
                for (int e = 0; e < 3; ++e) EXPECT_EQ(pb.position[j][e], pa.position[j][e]) << j << " sweep " << sweep;
            if (sweep < 3) pushTouched(pa), pushTouched(pb);
        }
        for (int i = 0; i < pb.size(); ++i) {
            for (int e = 0; e < 3; ++e) EXPECT_EQ(pb.position[i][e], pa.position[i][e]) << i << " path " << int(path);
            for (int e = 0; e < 4; ++e)
                EXPECT_EQ(pb.orientation[i].coeffs()[e], pa.orientation[i].coeffs()[e]) << i << " path " << int(path);
        }
        EXPECT_NE(pb.position[0], start.particles().position[0]); // the sweeps did move them
    }
    if (paths < 2) GTEST_SKIP() << "no AVX2 here: only the portable path was compared";
}

TEST(ShapeMatching, AnAcceleratedRunExtrapolatesEachSweepsMotionTheSameOnEveryPath) {
    // projectAllInRun with omega: each sweep's motion δ (from x before it, touched particles
    // pushed in between as contacts push them) becomes Δ = ω δ + (ω − 1) Δ_last, written here
    // in Eigen's arithmetic on projectAll's sweeps: the same bits on both paths. Fails if a
    // sweep's start, its Δ or a touched particle's push is lost.
    const auto start = jitteredRunBlock(29);
    const double omegas[4] = {1.0, 1.3, 1.2, 1.15};
    int paths = 0;
    for (const SimdPath path : {SimdPath::Portable, SimdPath::Avx2}) {
        if (!simdPathAvailable(path)) continue;
        ++paths;
        auto reference = start, inRun = start;
        auto &pa = reference.particles(), &pb = inRun.particles();
        reference.groups().refreshMoments(pa, pa.orientation, path);
        inRun.groups().refreshMoments(pb, pb.orientation, path);
        std::vector<Eigen::Vector3d> delta(size_t(pa.size()));
        for (int sweep = 0; sweep < 4; ++sweep) {
            const auto before = pa.position;
            reference.groups().projectAll(pa, pa.position, pa.orientation, 0.4, 2, 1e-3, path);
            for (int i = 0; i < pa.size(); ++i)
                for (int e = 0; e < 3; ++e) {
                    const double moved = pa.position[i][e] - before[i][e];
                    if (sweep == 0) {
                        delta[i][e] = moved;
                        continue;
                    }
                    delta[i][e] = omegas[sweep] * moved + (omegas[sweep] - 1.0) * delta[i][e];
                    pa.position[i][e] = before[i][e] + delta[i][e];
                }
            inRun.groups().projectAllInRun(pb, pb.position, pb.orientation, 0.4, 2, 1e-3, path, sweep == 0, sweep == 3,
                                           touched, omegas[sweep]);
            for (int j : touched)
                for (int e = 0; e < 3; ++e) EXPECT_EQ(pb.position[j][e], pa.position[j][e]) << j << " sweep " << sweep;
            if (sweep < 3) pushTouched(pa), pushTouched(pb);
        }
        for (int i = 0; i < pb.size(); ++i) {
            for (int e = 0; e < 3; ++e) EXPECT_EQ(pb.position[i][e], pa.position[i][e]) << i << " path " << int(path);
            for (int e = 0; e < 4; ++e)
                EXPECT_EQ(pb.orientation[i].coeffs()[e], pa.orientation[i].coeffs()[e]) << i << " path " << int(path);
        }
        // Not the plain sweeps: the extrapolation moved them further.
        auto plain = start;
        auto& pc = plain.particles();
        plain.groups().refreshMoments(pc, pc.orientation, path);
        for (int sweep = 0; sweep < 4; ++sweep) {
            plain.groups().projectAll(pc, pc.position, pc.orientation, 0.4, 2, 1e-3, path);
            if (sweep < 3) pushTouched(pc);
        }
        EXPECT_GT((pc.position[0] - pb.position[0]).norm(), 1e-6);
    }
    if (paths < 2) GTEST_SKIP() << "no AVX2 here: only the portable path was compared";
}

TEST(ShapeMatching, ARunOfSweepsRefusesATouchedParticleOutsideThePositions) {
    if (!simdPathAvailable(SimdPath::Avx2)) GTEST_SKIP() << "the run keeps its copy on the AVX2 path only";
    auto solver = test::blockSolver(cubeBlock(2, 2, 2, 0.1));
    auto& p = solver.particles();
    solver.groups().refreshMoments(p, p.orientation, SimdPath::Avx2);
    const auto sweep = [&](std::span<Eigen::Vector3d> x, bool first, std::vector<int> touched) {
        solver.groups().projectAllInRun(p, x, p.orientation, 0.6, 2, 1e-3, SimdPath::Avx2, first, false, touched);
    };
    EXPECT_THROW(sweep(p.position, true, {0, p.size()}), InputError);
    EXPECT_THROW(sweep(p.position, true, {-1}), InputError);
    sweep(p.position, true, {0});
    std::vector<Eigen::Vector3d> other(p.position.begin(), p.position.end() - 1);
    EXPECT_THROW(sweep(other, false, {0}), std::logic_error); // a later sweep over other positions
}

// Eigen's own turn of one orientation q toward a group's fit (what project() did one centre at
// a time before it turned a batch's centres on lanes): on the shortest arc, the normalised
// linear blend within about 1.6°, slerp beyond.
Eigen::Quaterniond turnedToward(const Eigen::Quaterniond& q, Eigen::Quaterniond target, double s) {
    if (target.dot(q) < 0.0) target.coeffs() = -target.coeffs();
    if (s >= 1.0) return target;
    if (q.dot(target) < 0.9999) return q.slerp(s, target).normalized();
    return Eigen::Quaterniond(q.coeffs() + s * (target.coeffs() - q.coeffs())).normalized();
}

// A block with its positions shaken and every particle turned: by 0.01 rad (a centre that then
// blends toward its fit) or by 0.5 rad (slerps), alternately; particle 7 fixed.
OrientedSolver shakenBlock() {
    std::mt19937 rng(31);
    auto solver = test::blockSolver(cubeBlock(6, 2, 5, 0.1));
    auto& p = solver.particles();
    for (int i = 0; i < p.size(); ++i) {
        p.position[i] += test::randomVector(rng, 0.02);
        const double angle = i % 2 ? 0.5 : 0.01;
        p.orientation[i] = Eigen::Quaterniond(Eigen::AngleAxisd(angle, test::randomVector(rng, 1).normalized()));
        if (i % 3 == 0) p.orientation[i].coeffs() = -p.orientation[i].coeffs(); // the long way round
    }
    p.fixed[7] = 1;
    return solver;
}

TEST(ShapeMatching, CachedMomentsAreEigensMomentsOnEveryPath) {
    // refreshMoments caches R(q_j) C_j of every particle, 4 at a time in lanes on AVX2: bit for
    // bit particles.moment's (Eigen's rotation matrix and product), also for a quaternion a
    // little off unit and for a count that leaves idle lanes (21 particles); a path the
    // processor lacks throws.
    std::mt19937 rng(8);
    auto solver = test::blockSolver(cubeBlock(7, 1, 3, 0.1));
    auto& p = solver.particles();
    ASSERT_EQ(p.size() % kRotationLanes, 1);
    for (int i = 0; i < p.size(); ++i) {
        p.orientation[i] = Eigen::Quaterniond(Eigen::AngleAxisd(0.3 * i, test::randomVector(rng, 1).normalized()));
        p.orientation[i].coeffs() *= 1.0 + 1e-7 * (i % 5);
    }
    for (const SimdPath path : {SimdPath::Portable, SimdPath::Avx2}) {
        if (!simdPathAvailable(path)) {
            EXPECT_THROW(solver.groups().refreshMoments(p, p.orientation, path), InputError);
            continue;
        }
        solver.groups().refreshMoments(p, p.orientation, path);
        const auto cached = solver.groups().cachedMoments();
        ASSERT_EQ(cached.size(), size_t(p.size()));
        for (int i = 0; i < p.size(); ++i) {
            const Eigen::Matrix3d expected = p.moment(i, p.orientation[i]);
            EXPECT_EQ(std::memcmp(cached[size_t(i)].data(), expected.data(), sizeof(expected)), 0)
                << "particle " << i << " path " << int(path);
        }
    }
}

TEST(ShapeMatching, TheMomentIsItsSumMemberByMember) {
    // moment(g) = Σ_j (x_j − o)(m_j r̄_j)ᵀ + Σ_j R_j C_j, o the centre particle's position, each
    // entry of each sum added member by member in the group's order: bit for bit this plain
    // sum, whatever the moment code keeps ready (the products m_j r̄_j are stored with the rest
    // data; the same bits as made here).
    std::mt19937 rng(23);
    auto solver = test::blockSolver(cubeBlock(4, 3, 2, 0.1));
    auto& p = solver.particles();
    for (int i = 0; i < p.size(); ++i) {
        p.position[i] += test::randomVector(rng, 0.03);
        p.orientation[i] = test::randomRotation(rng);
    }
    const ShapeMatchingGroups& groups = solver.groups();
    for (int g = 0; g < groups.size(); ++g) {
        const auto members = groups.members(g);
        double M = 0.0; // the rest centre as the groups make it
        Eigen::Vector3d restCentre = Eigen::Vector3d::Zero();
        for (int j : members) {
            M += p.mass[j];
            restCentre += p.mass[j] * p.restPosition[j];
        }
        restCentre /= M;
        Eigen::Matrix3d outer = Eigen::Matrix3d::Zero(), rotated = Eigen::Matrix3d::Zero();
        for (int j : members) {
            const Eigen::Vector3d d = p.position[j] - p.position[members[0]];
            const Eigen::Vector3d restOffset = p.restPosition[j] - restCentre;
            const Eigen::Matrix3d C = p.moment(j, p.orientation[j]);
            for (int i = 0; i < 3; ++i)
                for (int k = 0; k < 3; ++k) {
                    outer(i, k) += d[i] * (restOffset[k] * p.mass[j]);
                    rotated(i, k) += C(i, k);
                }
        }
        const Eigen::Matrix3d expected = outer + rotated;
        const Eigen::Matrix3d A = groups.moment(g, p, p.position, p.orientation);
        EXPECT_EQ(std::memcmp(A.data(), expected.data(), sizeof(expected)), 0) << "group " << g;
    }
}

TEST(ShapeMatching, TheCentreTurnsTowardItsFitAsEigenTurnsOneOrientation) {
    // project() turns a group's centre (and no other member) toward the group's fit; the
    // centres of a batch turn together on lanes, bit for bit as Eigen turns one quaternion,
    // by blend and by slerp, at partial and full stiffness; a fixed centre does not turn.
    for (const double stiffness : {0.6, 1.0}) {
        auto solver = shakenBlock();
        auto& p = solver.particles();
        ShapeMatchingGroups& groups = solver.groups();
        groups.refreshMoments(p, p.orientation);
        int blends = 0, slerps = 0;
        for (int g = 0; g < groups.size(); ++g) {
            const int c = groups.members(g)[0];
            const Eigen::Quaterniond before = p.orientation[c];
            groups.project(g, p, p.position, p.orientation, stiffness, 2, 1e-3);
            const Eigen::Quaterniond fit = groups.rotation(g);
            const Eigen::Quaterniond expected = p.fixed[c] ? before : turnedToward(before, fit, stiffness);
            for (int e = 0; e < 4; ++e) EXPECT_EQ(p.orientation[c].coeffs()[e], expected.coeffs()[e]) << "group " << g;
            if (std::abs(before.dot(fit)) < 0.9999) ++slerps; else ++blends;
        }
        EXPECT_GT(blends, 0);
        EXPECT_GT(slerps, 0);
    }
}

TEST(ShapeMatching, TheMomentsASweepKeepsAreTheMomentsOfItsTurns) {
    // A sweep keeps each turned centre's moment R_c C_c for the next sweep's sums, computed on
    // lanes: two sweeps give the same bits as two with refreshMoments (Eigen's moment of each
    // particle) between them, on every path.
    for (const SimdPath path : {SimdPath::Portable, SimdPath::Avx2}) {
        if (!simdPathAvailable(path)) continue;
        auto kept = shakenBlock(), fresh = shakenBlock();
        for (OrientedSolver* s : {&kept, &fresh}) {
            auto& p = s->particles();
            s->groups().refreshMoments(p, p.orientation);
            s->groups().projectAll(p, p.position, p.orientation, 0.6, 2, 1e-3, path);
            if (s == &fresh) s->groups().refreshMoments(p, p.orientation);
            s->groups().projectAll(p, p.position, p.orientation, 0.6, 2, 1e-3, path);
        }
        for (int i = 0; i < kept.particles().size(); ++i) {
            for (int e = 0; e < 3; ++e)
                EXPECT_EQ(kept.particles().position[i][e], fresh.particles().position[i][e]) << i << " path " << int(path);
            for (int e = 0; e < 4; ++e)
                EXPECT_EQ(kept.particles().orientation[i].coeffs()[e], fresh.particles().orientation[i].coeffs()[e])
                    << i << " path " << int(path);
        }
    }
}

TEST(ShapeMatching, RigidlyMovedRestPoseNeedsNoCorrection) {
    std::mt19937 rng(5);
    auto solver = test::blockSolver(cubeBlock(4, 3, 2, 0.1));
    const Eigen::Quaterniond R = test::randomRotation(rng);
    const Eigen::Vector3d t(12.0, -3.0, 40.0); // far from the origin on purpose
    moveRigidly(solver.particles(), R, t);
    const auto before = solver.particles();
    projectAll(solver);
    for (int i = 0; i < before.size(); ++i) {
        // 1e-12 m at 40 m from the origin is a few ulps of the coordinates.
        EXPECT_LT((solver.particles().position[i] - before.position[i]).norm(), 1e-12) << i;
        EXPECT_LT(solver.particles().orientation[i].angularDistance(before.orientation[i]), 1e-9) << i;
    }
}

TEST(ShapeMatching, ProjectionKeepsLinearMomentumAndPointAngularMomentum) {
    // Each group moves its members by m-weighted goals about their own centre, so Σ m Δx = 0;
    // for point particles (C = 0) R is the polar factor of Σ m p qᵀ, so Σ m x × Δx = 0 too.
    std::mt19937 rng(9);
    const auto block = cubeBlock(3, 3, 2, 0.1);
    auto particles = particlesFromPrimitives(block.primitives, 1000.0, "block");
    for (auto& C : particles.restMoment) C.setZero();
    OrientedSolver solver("points", particles, block.connections, {});
    auto& p = solver.particles();
    for (auto& x : p.position) x += test::randomVector(rng, 0.02);
    solver.groups().refreshMoments(p, p.orientation);
    for (int g = 0; g < solver.groups().size(); ++g) {
        const auto before = p.position;
        solver.groups().project(g, p, p.position, p.orientation, 0.7, 50);
        Eigen::Vector3d linear = Eigen::Vector3d::Zero(), angular = Eigen::Vector3d::Zero();
        double scale = 0.0;
        for (int j = 0; j < p.size(); ++j) {
            const Eigen::Vector3d dx = p.position[j] - before[j];
            linear += p.mass[j] * dx;
            angular += p.mass[j] * before[j].cross(dx);
            scale += p.mass[j] * dx.norm();
        }
        ASSERT_GT(scale, 0.0);
        EXPECT_LT(linear.norm(), 1e-9 * scale) << "group " << g;
        EXPECT_LT(angular.norm(), 1e-9 * scale) << "group " << g; // positions are O(0.3 m)
    }
}

TEST(ShapeMatching, StiffnessOneRecoversTheRestShape) {
    std::mt19937 rng(2);
    auto solver = test::blockSolver(cubeBlock(5, 3, 2, 0.1));
    auto& p = solver.particles();
    moveRigidly(p, test::randomRotation(rng), Eigen::Vector3d(1, 2, 3));
    for (int i = 0; i < p.size(); ++i) {
        p.position[i] += test::randomVector(rng, 0.03);
        p.orientation[i] = Eigen::Quaterniond(Eigen::AngleAxisd(0.2, test::randomVector(rng, 1).normalized())) *
                           p.orientation[i];
    }
    for (int sweep = 0; sweep < 400; ++sweep) projectAll(solver);
    // The result is a rigid motion of the rest shape: every pairwise distance is the rest one.
    EXPECT_LT(p.restShapeError(), 1e-6); // m, for 0.1 m cubes after 400 sweeps (converges geometrically)
    // And orientations agree with each other (one rigid rotation).
    for (int i = 1; i < p.size(); ++i) EXPECT_LT(p.orientation[i].angularDistance(p.orientation[0]), 1e-5);
}

TEST(PrimitiveDeformation, IdentityAtRestAndTheRotationUnderARigidMotion) {
    std::mt19937 rng(4);
    const auto block = cubeBlock(3, 2, 2, 0.1);
    auto solver = test::blockSolver(block);
    for (int i = 0; i < solver.particles().size(); ++i)
        EXPECT_LT((solver.deformation(i) - Eigen::Matrix3d::Identity()).norm(), 1e-12);
    const Eigen::Quaterniond R = test::randomRotation(rng);
    moveRigidly(solver.particles(), R, Eigen::Vector3d(0.5, 0, 0));
    for (int i = 0; i < solver.particles().size(); ++i)
        EXPECT_LT((solver.deformation(i) - R.toRotationMatrix()).norm(), 1e-12);
    // Deformed vertices are then the rigidly moved primitive vertices.
    std::vector<Eigen::Vector3d> vertices;
    PrimitiveDeformation(solver.particles(), block.primitives).deformedVertices(solver, vertices);
    size_t j = 0; // flat: primitive after primitive
    for (const auto& primitive : block.primitives)
        for (const Eigen::Vector3d& v : primitive.vertices())
            EXPECT_LT((vertices[j++] - (R * v + Eigen::Vector3d(0.5, 0, 0))).norm(), 1e-12);
    EXPECT_EQ(j, vertices.size());
}

TEST(PrimitiveDeformation, RecoversAPrescribedAffineMap) {
    // Particles placed by x = F x̄ + t. D = A Ā⁻¹ is the best-fit affine map; the particles'
    // own moments (which stay rigid) pull it towards their rotation by a fraction
    // ~ C_i / (m_i spacing²). With cubes of side 1 mm on a 0.1 m lattice that fraction is
    // ~1e-4, so D must equal F within 1e-3 (relative).
    const auto block = cubeBlock(3, 3, 3, 0.1);
    auto particles = particlesFromPrimitives(block.primitives, 1000.0, "block");
    for (auto& C : particles.restMoment) C *= 1e-4; // 1 mm cubes at the same centres
    OrientedSolver solver("affine", particles, block.connections, {});
    Eigen::Matrix3d F;
    F << 1.1, 0.2, 0.0, -0.1, 0.9, 0.05, 0.0, 0.1, 1.2;
    auto& p = solver.particles();
    for (int i = 0; i < p.size(); ++i) p.position[i] = F * p.restPosition[i] + Eigen::Vector3d(0.3, 0.1, 0);
    const int centre = 13; // the middle cube: its group is the full 3×3×3 block
    EXPECT_LT((solver.deformation(centre) - F).norm(), 1e-3 * F.norm());
}

TEST(PrimitiveDeformation, AllGroupsAtOnceEqualEachGroupAlone) {
    // deformations() shares each particle's moment between the groups that hold it; the sums
    // are the same, term by term, so every matrix is deformation(g)'s to the bit.
    std::mt19937 rng(17);
    auto solver = test::blockSolver(cubeBlock(4, 3, 3, 0.1));
    auto& p = solver.particles();
    for (int i = 0; i < p.size(); ++i) {
        p.position[i] += test::randomVector(rng, 0.03);
        p.orientation[i] = test::randomRotation(rng);
    }
    int paths = 0;
    for (const SimdPath path : {SimdPath::Portable, SimdPath::Avx2}) { // the same bits on every path
        if (!simdPathAvailable(path)) {
            EXPECT_THROW(solver.groups().deformations(p, p.position, p.orientation, path), InputError);
            continue;
        }
        ++paths;
        const auto all = solver.groups().deformations(p, p.position, p.orientation, path);
        ASSERT_EQ(int(all.size()), solver.groups().size());
        for (int g = 0; g < solver.groups().size(); ++g)
            EXPECT_EQ(std::memcmp(all[size_t(g)].data(), solver.deformation(g).data(), 9 * sizeof(double)), 0) // -0 too
                << "group " << g << ", path " << int(path);
    }
    if (paths < 2) GTEST_SKIP() << "no AVX2 here: only the portable path was compared";
}

} // namespace
} // namespace shatter::oriented
