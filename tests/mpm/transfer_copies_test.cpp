// The copies of the transfer loops (TransferTargets.h): the x86-64-v3 one, whose far
// particles of the cubic kernel take the Double4 path, and the generic one. Both must give the
// same motion up to rounding; on a CPU without x86-64-v3 only the generic copy exists. The
// x86-64-v4 copies must give the x86-64-v3 copies' bits.
#include "TestScenes.h"
#include <shatter/plugin/mpm/Solver2D.h>
#include <shatter/plugin/mpm/TransferTargets.h>

#include <gtest/gtest.h>

#include <cmath>
#include <utility>

namespace shatter::mpm {
namespace {

// Restores the CPU's own choice when a test ends, also when it fails.
struct GenericTransfers {
    explicit GenericTransfers(bool force) { forceGenericTransfers() = force; }
    ~GenericTransfers() { forceGenericTransfers() = false; }
};
struct V3Transfers {
    V3Transfers() { forceX86_64_v3Transfers() = true; }
    ~V3Transfers() { forceX86_64_v3Transfers() = false; }
};

// A spinning disk with a crack through part of it (both the far and the near-crack paths of
// the transfers), landing on the ground; 0.15 s, about 60 substeps.
Solver2D runDisk(bool generic, KernelType kernel, ConstitutiveModelType model = ConstitutiveModelType::Corotated) {
    const GenericTransfers copy(generic);
    Scene s = test::diskScene(0.1, test::elastic(model, 1e5, 0.3, 1000), Vec2(0, 0.52), 0.5, Vec2(0.7, -2));
    s.grid.kernel = kernel;
    s.gravity = Vec2(0, -9.81);
    s.colliders.push_back(test::ground(0));
    s.cracks.push_back(CrackSpec{{Vec2(-0.2, 0.5), Vec2(0.2, 0.6)}, false, TipSelection::None, {}});
    Solver2D solver(s);
    auto& P = solver.mutableParticles();
    for (size_t p = 0; p < P.size(); ++p) {
        const Vec2 r = P.x[p] - Vec2(0, 0.52);
        P.v[p] += 3.0 * Vec2(-r.y(), r.x());
    }
    solver.advance(0.15);
    return solver;
}

TEST(TransferCopies, GenericAndX86_64_v3CopiesAgreeToRounding) {
    if (!runsX86_64_v3()) GTEST_SKIP() << "this CPU runs only the generic copy";
    for (KernelType kernel : {KernelType::Cubic, KernelType::Quadratic}) {
        const Solver2D wide = runDisk(false, kernel), generic = runDisk(true, kernel);
        ASSERT_EQ(wide.substeps(), generic.substeps());
        const auto &a = wide.particles(), &b = generic.particles();
        double largestDx = 0, largestDv = 0, largestV = 0;
        for (size_t p = 0; p < a.size(); ++p) {
            largestDx = std::max(largestDx, (a.x[p] - b.x[p]).norm());
            largestDv = std::max(largestDv, (a.v[p] - b.v[p]).norm());
            largestV = std::max(largestV, a.v[p].norm());
        }
        // Fused multiply-adds and the vector path's order of sums change the last bits of each
        // substep, and the disk hits the ground, so differences grow, but stay far below any
        // physical scale: 1e-9 of a cell in position, 1e-9 of the largest speed.
        EXPECT_LT(largestDx, 1e-10) << int(kernel);
        EXPECT_LT(largestDv, 1e-9 * largestV) << int(kernel);
        // And the two runs did take different copies (else this test would prove nothing): the
        // cubic kernel's Double4 path sums in another order (the quadratic one differs only by
        // fused multiply-adds, which an unoptimised build does not form).
        if (kernel == KernelType::Cubic) {
            EXPECT_GT(largestDx, 0);
        }
    }
}

// The x86-64-v4 copies do the x86-64-v3 copies' operations per node and per particle, two
// nodes (scatter) or two particles (gather) per instruction: the same bits. Also for snow,
// whose plastic return the pair gather's fast path must not skip (hasReturnMapping).
TEST(TransferCopies, X86_64_v4AndV3CopiesGiveTheSameBits) {
    if (!runsX86_64_v4()) GTEST_SKIP() << "this CPU has no AVX-512 (x86-64-v4)";
    const std::pair<KernelType, ConstitutiveModelType> cases[] = {{KernelType::Cubic, ConstitutiveModelType::Corotated},
                                                                  {KernelType::Quadratic, ConstitutiveModelType::Corotated},
                                                                  {KernelType::Cubic, ConstitutiveModelType::Snow}};
    for (const auto& c : cases) {
        const KernelType kernel = c.first; // not a structured binding: clang 14 cannot capture those
        const ConstitutiveModelType model = c.second;
        SCOPED_TRACE(::testing::Message() << "kernel " << int(kernel) << " model " << int(model));
        const Solver2D v4 = runDisk(false, kernel, model);
        bool v3Ran = false;
        const Solver2D v3 = [&] {
            const V3Transfers copy;
            v3Ran = !runsX86_64_v4();
            return runDisk(false, kernel, model);
        }();
        ASSERT_TRUE(v3Ran);
        ASSERT_EQ(v4.substeps(), v3.substeps());
        const auto &a = v4.particles(), &b = v3.particles();
        size_t yielded = 0;
        for (size_t p = 0; p < a.size(); ++p) {
            ASSERT_EQ(a.x[p], b.x[p]) << p;
            ASSERT_EQ(a.v[p], b.v[p]) << p;
            ASSERT_EQ(a.Fe[p], b.Fe[p]) << p;
            ASSERT_EQ(a.C[p], b.C[p]) << p;
            ASSERT_EQ(a.Fp[p], b.Fp[p]) << p;
            if (a.Fp[p] != Mat2::Identity()) ++yielded;
        }
        if (model == ConstitutiveModelType::Snow) {
            EXPECT_GT(yielded, a.size() / 2) << "the snow disk yields (measured: every particle)";
        }
    }
}

} // namespace
} // namespace shatter::mpm
