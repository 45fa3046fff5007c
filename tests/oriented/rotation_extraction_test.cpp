// Rotation extraction (Müller et al. 2016) and particle moments (source 000 §3.2.1).
#include "OrientedFixtures.h"
#include <shatter/plugin/common/InputError.h>
#include <shatter/plugin/oriented/ParticleMoment.h>
#include <shatter/plugin/oriented/RotationExtraction.h>
#include <shatter/plugin/oriented/RotationLanes.h>

#include <gtest/gtest.h>

#include <algorithm>

namespace shatter::oriented {
namespace {

// Converged extraction is exact to rounding: 1e-9 leaves room for the ~20 products.
constexpr double kTight = 1e-9;

double rotationError(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b) {
    return (a.toRotationMatrix() - b.toRotationMatrix()).norm();
}

TEST(RotationExtraction, RecoversTheRotationOfAStretchedRotation) {
    std::mt19937 rng(7);
    for (int trial = 0; trial < 50; ++trial) {
        const Eigen::Quaterniond R = test::randomRotation(rng);
        Eigen::Matrix3d S = Eigen::Matrix3d::Random();
        S = S * S.transpose() + 0.1 * Eigen::Matrix3d::Identity(); // symmetric positive definite
        const Eigen::Quaterniond q = extractRotation(R.toRotationMatrix() * S, Eigen::Quaterniond::Identity(), 200);
        EXPECT_LT(rotationError(q, R), 1e-7) << "trial " << trial;
    }
}

TEST(RotationExtraction, SingleSphereParticleGivesItsOwnOrientation) {
    // A = (m r²/5) R (source 000 eq. 2): the group of one particle returns that particle's R.
    std::mt19937 rng(3);
    const Eigen::Quaterniond R = test::randomRotation(rng);
    const Eigen::Matrix3d A = R.toRotationMatrix() * sphereMoment(2.0, 0.3);
    EXPECT_LT(rotationError(extractRotation(A, Eigen::Quaterniond::Identity(), 100), R), kTight);
}

TEST(RotationExtraction, CollinearAndCoplanarPointsGiveFiniteProperRotations) {
    // Point masses on a line (rank 1) and in a plane (rank 2), turned by R: the extracted
    // rotation is finite, proper, and maps the rest line/plane onto the current one.
    std::mt19937 rng(11);
    const Eigen::Quaterniond R = test::randomRotation(rng);
    const Eigen::Vector3d u(1, 0, 0), v(0, 1, 0);
    const Eigen::Matrix3d line = (R * u) * u.transpose();
    const Eigen::Matrix3d plane = line + (R * v) * v.transpose();
    for (const Eigen::Matrix3d& A : {line, plane}) {
        const Eigen::Quaterniond q = extractRotation(A, Eigen::Quaterniond::Identity(), 200);
        ASSERT_TRUE(q.coeffs().allFinite());
        EXPECT_NEAR(q.toRotationMatrix().determinant(), 1.0, kTight);
        EXPECT_LT((q * u - R * u).norm(), 1e-7);
    }
    const Eigen::Quaterniond planeFit = extractRotation(plane, Eigen::Quaterniond::Identity(), 200);
    EXPECT_LT((planeFit * v - R * v).norm(), 1e-7);
    EXPECT_LT(rotationError(planeFit, R), 1e-6); // two directions fix the third
}

TEST(RotationExtraction, ZeroAndReflectingMatricesStayFiniteProperRotations) {
    const Eigen::Quaterniond start(Eigen::AngleAxisd(0.4, Eigen::Vector3d(1, 2, 3).normalized()));
    const Eigen::Quaterniond zero = extractRotation(Eigen::Matrix3d::Zero(), start);
    EXPECT_LT(rotationError(zero, start), kTight); // nothing to fit: the warm start stays
    const Eigen::Matrix3d mirror = Eigen::Vector3d(1, 1, -1).asDiagonal();
    const Eigen::Quaterniond q = extractRotation(mirror, Eigen::Quaterniond::Identity(), 200);
    ASSERT_TRUE(q.coeffs().allFinite());
    EXPECT_NEAR(q.toRotationMatrix().determinant(), 1.0, kTight);
}

TEST(RotationExtraction, StoppingAfterASmallNewtonStepKeepsTheConvergedAnswer) {
    // A fit warm-started within 1e-9 rad of its answer stops after one Newton step (under
    // 1e-8 rad); what it returns is the converged rotation to rounding, not the warm start.
    std::mt19937 rng(13);
    for (int trial = 0; trial < 50; ++trial) {
        const Eigen::Quaterniond R = test::randomRotation(rng);
        Eigen::Matrix3d S = Eigen::Matrix3d::Random();
        S = S * S.transpose() + 0.1 * Eigen::Matrix3d::Identity();
        const Eigen::Matrix3d A = R.toRotationMatrix() * S;
        const Eigen::Vector3d axis = test::randomVector(rng, 1).normalized();
        const Eigen::Quaterniond near = R * Eigen::Quaterniond(Eigen::AngleAxisd(1e-9, axis));
        const Eigen::Quaterniond q = extractRotation(A, near, 200);
        EXPECT_LT(rotationError(q, R), 1e-13) << "trial " << trial;
        EXPECT_GT(rotationError(near, R), 1e-10) << "trial " << trial; // the warm start alone would fail
    }
}

TEST(RotationExtraction, FitsInABatchAreBitForBitFitsAloneOnEveryPath) {
    // extractRotations runs kRotationLanes fits at a time as interleaved lanes; each lane must
    // be extractRotation's answer exactly, whatever its neighbours do: here lanes that stop at
    // once (a zero matrix), take one Newton step, need large exact turns (far warm starts), or
    // run out of iterations, in full and partial batches, and more fits than lanes.
    constexpr int kMost = kRotationLanes + 3;
    std::mt19937 rng(17);
    for (int trial = 0; trial < 40; ++trial) {
        const int count = 1 + trial % kMost;
        const int iterations = 1 + trial % 5;
        Eigen::Matrix3d A[kMost];
        Eigen::Quaterniond q[kMost], alone[kMost];
        for (int l = 0; l < count; ++l) {
            const Eigen::Quaterniond R = test::randomRotation(rng);
            Eigen::Matrix3d S = Eigen::Matrix3d::Random();
            S = S * S.transpose() + 0.1 * Eigen::Matrix3d::Identity();
            A[l] = (trial + l) % 7 == 0 ? Eigen::Matrix3d::Zero() : Eigen::Matrix3d(R.toRotationMatrix() * S);
            const double off = (trial + l) % 3 == 0 ? 1.5 : 1e-4; // rad from the answer
            q[l] = R * Eigen::Quaterniond(Eigen::AngleAxisd(off, test::randomVector(rng, 1).normalized()));
            q[l].coeffs() *= 1.01; // off unit, as a warm start may be
            alone[l] = extractRotation(A[l], q[l], iterations, 1e-12, 1e-3);
        }
        // On the portable path (4 lanes as two SSE2 halves) and on AVX2 (one 4-wide vector)
        // where the processor has it: the same bits.
        for (const SimdPath path : {SimdPath::Portable, SimdPath::Avx2}) {
            if (!simdPathAvailable(path)) continue;
            Eigen::Quaterniond batched[kMost];
            std::copy(q, q + count, batched);
            extractRotations({A, size_t(count)}, {batched, size_t(count)}, iterations, 1e-12, 1e-3, path);
            for (int l = 0; l < count; ++l)
                for (int e = 0; e < 4; ++e)
                    EXPECT_EQ(batched[l].coeffs()[e], alone[l].coeffs()[e])
                        << "trial " << trial << " lane " << l << " path " << int(path);
        }
    }
    if (!simdPathAvailable(SimdPath::Avx2)) GTEST_SKIP() << "no AVX2 here: only the portable path was compared";
}

TEST(RotationExtraction, FitsOfLanesFilledOneByOneAreFitsAloneOnEveryPath) {
    // The batched projection writes its sums into RotationLanes (set) and fits them there
    // (fitRotations), full and partial (1 to kRotationLanes lanes, the rest empty fits).
    std::mt19937 rng(23);
    for (int count = 1; count <= kRotationLanes; ++count)
        for (const SimdPath path : {SimdPath::Portable, SimdPath::Avx2}) {
            if (!simdPathAvailable(path)) continue;
            RotationLanes lanes; // lanes not set: fits with nothing to fit
            Eigen::Quaterniond alone[kRotationLanes];
            for (int l = 0; l < count; ++l) {
                const Eigen::Quaterniond R = test::randomRotation(rng);
                const Eigen::Matrix3d A = R.toRotationMatrix() * (Eigen::Matrix3d::Identity() + 0.2 * Eigen::Matrix3d::Random());
                const Eigen::Quaterniond start = R * Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitX()));
                lanes.set(l, A, start);
                alone[l] = extractRotation(A, start, 3, 1e-12, 1e-3);
            }
            fitRotations(lanes, count, 3, 1e-12, 1e-3, path);
            for (int l = 0; l < count; ++l)
                for (int e = 0; e < 4; ++e)
                    EXPECT_EQ(lanes.answer(l).coeffs()[e], alone[l].coeffs()[e])
                        << "count " << count << " lane " << l << " path " << int(path);
        }
}

TEST(RotationExtraction, FitsOfLanesRefuseACountBeyondTheLanesAndAMissingPath) {
    RotationLanes lanes;
    EXPECT_THROW(fitRotations(lanes, kRotationLanes + 1, 3, 1e-12, 1e-3, SimdPath::Portable), InputError);
    EXPECT_THROW(fitRotations(lanes, -1, 3, 1e-12, 1e-3, SimdPath::Portable), InputError);
    if (!simdPathAvailable(SimdPath::Avx2)) {
        EXPECT_THROW(fitRotations(lanes, 1, 3, 1e-12, 1e-3, SimdPath::Avx2), InputError);
    }
    fitRotations(lanes, kRotationLanes, 3, 1e-12, 1e-3, SimdPath::Portable); // empty fits stay the identity
    for (int l = 0; l < kRotationLanes; ++l) EXPECT_EQ(lanes.answer(l).coeffs(), Eigen::Quaterniond::Identity().coeffs());
}

TEST(ParticleMoment, BoxMomentMatchesTheClosedForm) {
    // Solid box a × b × c of mass m: C = m/12 diag(a², b², c²).
    geometry::OrientedBox box;
    box.halfExtents = {0.3, 0.2, 0.05};
    const auto mass = geometry::boxPolyhedron(box).massProperties(700.0);
    const Eigen::Vector3d sides = 2.0 * box.halfExtents;
    const Eigen::Matrix3d expected = (mass.mass / 12.0 * sides.cwiseProduct(sides)).asDiagonal();
    EXPECT_LT((secondMoment(mass) - expected).norm(), 1e-12 * expected.norm());
    EXPECT_LT((inertiaFromMoment(secondMoment(mass)) - mass.inertia).norm(), 1e-12 * mass.inertia.norm());
}

TEST(ParticleMoment, SphereIsTheIsotropicEllipsoid) {
    const double m = 3.0, r = 0.2;
    EXPECT_LT((sphereMoment(m, r) - ellipsoidMoment(m, Eigen::Vector3d::Constant(r))).norm(), 1e-15);
    // Inertia of a solid sphere: 2/5 m r².
    EXPECT_NEAR(inertiaFromMoment(sphereMoment(m, r))(0, 0), 0.4 * m * r * r, 1e-15);
}

} // namespace
} // namespace shatter::oriented
