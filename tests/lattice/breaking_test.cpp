// Breaking, weakening, damage spreading, cleaving planes and noise (source 002 §2, §3.2).
#include "LatticeFixtures.h"
#include <shatter/plugin/lattice/CleavingPlane.h>
#include <shatter/plugin/lattice/FractureAnalysis.h>
#include <shatter/plugin/lattice/Fragments.h>
#include <shatter/plugin/lattice/Noise.h>
#include <shatter/plugin/lattice/TetGenerators.h>

#include <gtest/gtest.h>


namespace shatter::lattice {
namespace {

Eigen::VectorXd gravity(const Lattice& lattice, const LatticePiece& piece, double g = 9.81) {
    Eigen::VectorXd q = Eigen::VectorXd::Zero(3 * piece.particles.size());
    for (size_t i = 0; i < piece.particles.size(); ++i) q[3 * i + 1] = -g * lattice.particles()[piece.particles[i]].mass;
    return q;
}

FractureAnalysisSettings quiet() {
    FractureAnalysisSettings s;
    s.spreading.enabled = false;
    s.breaking.weakenByLoad = false;
    s.solver.tolerance = 1e-10;
    return s;
}

TEST(Breaking, HangingChainBreaksOnlyAtTheTopLink) {
    // Link k carries the weight of the k+1 tets below it; make only the top one too weak.
    const int n = 10;
    MaterialSettings m = adobe();
    Lattice probe(test::verticalChain(n), m);
    const double tetWeight = probe.particles()[0].mass * 9.81, area = probe.links()[0].area;
    m.strength = (n - 1.5) * tetWeight / area; // between the weights of n-2 and n-1 tets
    Lattice chain(test::verticalChain(n), m);
    chain.setFixed(n - 1, true);
    LatticePiece piece = makePiece(chain, test::indices(n));
    Random random(1);
    const FractureReport r = analyseFracture(chain, piece, gravity(chain, piece), Eigen::Vector3d::Zero(), quiet(), random);
    ASSERT_EQ(r.broken.size(), 1u);
    EXPECT_EQ(chain.links()[r.broken[0]].b, n - 1);
    EXPECT_NEAR(r.maxUtilisation, (n - 1) / (n - 1.5), 1e-6);
    // The chain below falls free: the second solve finds no force, so nothing else breaks.
    EXPECT_EQ(r.solves, 2);
    EXPECT_EQ(connectedComponents(chain, piece.particles).size(), 2u);
}

TEST(Breaking, NothingBreaksUnderGravityAloneAtDefaultMaterials) {
    for (const auto& name : materialNames()) {
        GeneratorOptions o;
        o.jitter = 0.15;
        Lattice wall(tetBox({2.0, 1.5, 0.3}, {20, 15, 3}, o), materialNamed(name));
        for (int t : tetsWithFaceOnPlane(wall.mesh(), {0, 1, 0}, -0.75, 1e-9)) wall.setFixed(t, true);
        LatticePiece piece = makePiece(wall, test::indices(wall.particleCount()));
        Random random(1);
        FractureAnalysisSettings s; // defaults: weakening and spreading on
        const FractureReport r = analyseFracture(wall, piece, gravity(wall, piece), Eigen::Vector3d::Zero(), s, random);
        EXPECT_TRUE(r.broken.empty()) << name;
        EXPECT_LT(r.maxUtilisation, 0.2) << name; // far from breaking: resting loads do not wear it
        EXPECT_TRUE(r.converged) << name;
    }
}

// A bar along x, fixed at its left end and pulled at its right end. The lattice is a
// mechanism (about 2 links per particle for 3 degrees of freedom), so a pull is held only near
// where it is applied: link forces fall off by about 3 per cell from the loaded end.
struct PullTest {
    // The loads below are chosen for this strength (the glass preset's may be recalibrated).
    static MaterialSettings material() {
        MaterialSettings m = glass();
        m.strength = 6e5;
        return m;
    }
    Lattice bar;
    LatticePiece piece;
    Eigen::VectorXd loads;
    PullTest(double force, const std::vector<CleavingPlane>& planes = {}, int across = 2)
        : bar(tetBox({1.0, 0.05 * across, 0.05 * across}, {20, across, across}), material()) {
        applyCleavingPlanes(bar, planes);
        const auto left = tetsWithFaceOnPlane(bar.mesh(), {1, 0, 0}, -0.5, 1e-9);
        const auto right = tetsWithFaceOnPlane(bar.mesh(), {1, 0, 0}, 0.5, 1e-9);
        for (int t : left) bar.setFixed(t, true);
        piece = makePiece(bar, test::indices(bar.particleCount()));
        loads = Eigen::VectorXd::Zero(3 * bar.particleCount());
        for (int t : right) loads[3 * t] = force / double(right.size());
    }
};

TEST(Breaking, ForcesAreSolvedAgainUntilNothingMoreBreaks) {
    // A tet held by four fixed neighbours and pushed: once its weakest link goes, the other
    // three must carry the whole load, which one solve alone would never see.
    auto build = [] {
        Lattice star(test::starOfFive(), concrete());
        for (int i = 1; i < 5; ++i) star.setFixed(i, true);
        return star;
    };
    Lattice probe = build();
    LatticePiece probePiece = makePiece(probe, test::indices(5));
    Eigen::VectorXd loads = Eigen::VectorXd::Zero(15);
    loads.segment<3>(0) = Eigen::Vector3d(-2e5, -1e5, -3e5);
    const ConstraintSystem full = probePiece.constraintSystem(probe); // a copy: rebuild() replaces it
    Eigen::VectorXd before, after;
    full.solve(full.rightHandSide(loads, Eigen::Vector3d::Zero()), before, quiet().solver);
    // The weakest link fails first; choose strengths so that only it fails in the first solve
    // but a survivor fails once it is gone.
    int weakest = 0;
    for (int k = 1; k < 4; ++k)
        if (std::abs(before[k]) > std::abs(before[weakest])) weakest = k;
    probe.breakLink(full.links()[weakest]);
    probePiece.rebuild(probe);
    probePiece.constraintSystem(probe).solve(probePiece.constraintSystem(probe).rightHandSide(loads, Eigen::Vector3d::Zero()),
                                             after, quiet().solver);
    const ConstraintSystem& rest = *probePiece.system;
    double gain = 0.0;
    int next = -1;
    for (int k = 0; k < rest.rowCount(); ++k) {
        const int row = int(std::find(full.links().begin(), full.links().end(), rest.links()[k]) - full.links().begin());
        const double g = tensileEquivalent(after[k], 10.0) / tensileEquivalent(before[row], 10.0);
        if (g > gain) gain = g, next = rest.links()[k];
    }
    ASSERT_GT(gain, 1.1) << "the survivors must take more load";
    auto run = [&](int rounds) {
        Lattice star = build();
        for (int k = 0; k < star.linkCount(); ++k) {
            const int row = int(std::find(full.links().begin(), full.links().end(), k) - full.links().begin());
            const double load = tensileEquivalent(before[row], 10.0);
            // Just below the first solve's load everywhere but the weakest link, which is at 80%.
            star.scaleStrength(k, (k == full.links()[weakest] ? 0.8 : (k == next ? 1.05 : 2.0 * gain)) * load /
                                      star.links()[k].strength);
        }
        LatticePiece piece = makePiece(star, test::indices(5));
        FractureAnalysisSettings s = quiet();
        s.breaking.maxRounds = rounds;
        Random random(1);
        const FractureReport r = analyseFracture(star, piece, loads, Eigen::Vector3d::Zero(), s, random);
        return std::make_pair(r, int(connectedComponents(star, piece.particles).size()));
    };
    const auto [once, onceParts] = run(1);
    const auto [again, againParts] = run(64);
    EXPECT_EQ(once.broken.size(), 1u);
    EXPECT_GE(again.broken.size(), 2u);
    EXPECT_GT(again.solves, 2);
    // One broken link frees one fixed neighbour; the cascade frees more.
    EXPECT_EQ(onceParts, 2);
    EXPECT_GT(againParts, onceParts);
}

TEST(Breaking, CleavingPlaneMakesTheBreakFollowThePlane) {
    // A bar pulled at one end: a pull that breaks nothing in the plain bar breaks it on the
    // plane, and only there.
    CleavingPlane plane;
    plane.point = Eigen::Vector3d(0.45, 0, 0); // between the last two cells of the bar
    plane.normal = Eigen::Vector3d(1, 0, 0);
    plane.factor = 0.2;
    Random random(1);
    PullTest plain(1e4), cleaved(1e4, {plane});
    analyseFracture(plain.bar, plain.piece, plain.loads, Eigen::Vector3d::Zero(), quiet(), random);
    analyseFracture(cleaved.bar, cleaved.piece, cleaved.loads, Eigen::Vector3d::Zero(), quiet(), random);
    EXPECT_EQ(plain.bar.brokenCount(), 0);
    EXPECT_GT(cleaved.bar.brokenCount(), 0);
    for (const Link& l : cleaved.bar.links()) {
        if (l.broken) {
            EXPECT_TRUE(faceNearPlane(cleaved.bar, l, plane));
        }
    }
}

TEST(Breaking, CleavedHangingChainComesApartAtThePlaneNotAtTheTop) {
    // The top link carries the most; a plane across the middle link makes that one give way,
    // and the chain comes apart exactly there.
    const int n = 12;
    MaterialSettings m = adobe();
    const Lattice probe(test::verticalChain(n), m);
    const double w = probe.particles()[0].mass * 9.81;
    m.strength = 1.2 * (n - 1) * w / probe.links()[0].area; // the top link holds 83% of this
    Lattice chain(test::verticalChain(n), m);
    chain.setFixed(n - 1, true);
    CleavingPlane plane;
    plane.point = chain.links()[n / 2].faceCentre;
    plane.normal = Eigen::Vector3d(0, 1, 0);
    plane.factor = 0.3; // the middle link carries n/2 weights, above 0.3 of the strength
    applyCleavingPlanes(chain, {plane});
    LatticePiece piece = makePiece(chain, test::indices(n));
    Random random(1);
    const FractureReport r = analyseFracture(chain, piece, gravity(chain, piece), Eigen::Vector3d::Zero(), quiet(), random);
    ASSERT_EQ(r.broken.size(), 1u);
    EXPECT_TRUE(faceNearPlane(chain, chain.links()[r.broken[0]], plane));
    const auto parts = connectedComponents(chain, piece.particles);
    ASSERT_EQ(parts.size(), 2u);
    for (const auto& part : parts) {
        const bool below = chain.particles()[part[0]].position.y() < plane.point.y();
        for (int p : part) EXPECT_EQ(chain.particles()[p].position.y() < plane.point.y(), below);
    }
}

// A free slab (0.8 × 0.4 m, one 4 cm cell thick) pinched across its cleaving plane x = 0 near
// one edge: the pinch breaks the plane's links near it. Where the plane's crack runs, it parts
// the slab into its two halves along the whole plane; otherwise the pinch's forces fall off
// within a few cells and the slab stays one piece. A link of infinite strength (a bound
// sliver) on the plane stops the run there.
struct PinchedSlab {
    Lattice slab;
    CleavingPlane plane;
    FractureReport report;

    explicit PinchedSlab(bool runs, int unbreakable = -1) : slab(tetSlab(0.8, 0.4, 0.04, 0.04), glass()) {
        plane.point = Eigen::Vector3d::Zero();
        plane.normal = Eigen::Vector3d::UnitX();
        plane.distance = 0.005;
        plane.factor = 0.3;
        plane.crackRuns = runs;
        applyCleavingPlanes(slab, {plane});
        if (unbreakable >= 0) slab.scaleStrength(unbreakable, INFINITY);
        LatticePiece piece = makePiece(slab, test::indices(slab.particleCount()));
        Eigen::VectorXd loads = Eigen::VectorXd::Zero(3 * slab.particleCount());
        for (int p = 0; p < slab.particleCount(); ++p) {
            const Eigen::Vector3d& at = slab.particles()[p].position;
            if (std::abs(at.x()) < 0.04 && at.z() < -0.16) loads[3 * p] = at.x() < 0 ? -2e3 : 2e3;
        }
        Random random(1);
        report = analyseFracture(slab, piece, loads, Eigen::Vector3d::Zero(), quiet(), random);
    }
    int brokenOnPlane() const {
        int n = 0;
        for (const Link& l : slab.links()) n += l.broken && faceNearPlane(slab, l, plane);
        return n;
    }
    int onPlane() const {
        int n = 0;
        for (const Link& l : slab.links()) n += faceNearPlane(slab, l, plane);
        return n;
    }
};

TEST(Breaking, ACrackThatReachesARunningPlaneRunsAlongIt) {
    const PinchedSlab held(false), parted(true);
    EXPECT_GT(held.brokenOnPlane(), 0) << "the pinch should break the plane near it";
    EXPECT_LT(held.brokenOnPlane(), held.onPlane() / 2);
    EXPECT_EQ(connectedComponents(held.slab, test::indices(held.slab.particleCount())).size(), 1u);
    EXPECT_EQ(parted.brokenOnPlane(), parted.onPlane());
    const auto halves = connectedComponents(parted.slab, test::indices(parted.slab.particleCount()));
    ASSERT_EQ(halves.size(), 2u);
    for (const auto& half : halves) {
        EXPECT_EQ(int(half.size()), parted.slab.particleCount() / 2);
        const bool left = parted.slab.particles()[half[0]].position.x() < 0;
        for (int p : half) EXPECT_EQ(parted.slab.particles()[p].position.x() < 0, left);
    }
    // A link of the plane far from the pinch that cannot break (a bound sliver) holds the
    // halves together.
    int far = -1;
    for (int k = 0; k < parted.slab.linkCount(); ++k)
        if (faceNearPlane(parted.slab, parted.slab.links()[k], parted.plane) && parted.slab.links()[k].faceCentre.z() > 0.15) far = k;
    ASSERT_GE(far, 0);
    const PinchedSlab bound(true, far);
    EXPECT_FALSE(bound.slab.links()[far].broken);
    EXPECT_EQ(bound.brokenOnPlane(), bound.onPlane() - 1);
    EXPECT_EQ(connectedComponents(bound.slab, test::indices(bound.slab.particleCount())).size(), 1u);
}

TEST(Breaking, LoadsNearTheStrengthWeakenLinksAndLighterOnesDoNot) {
    PullTest heavy(1e4), light(4e3); // largest force/capacity 0.8 and 0.32
    FractureAnalysisSettings s = quiet();
    s.breaking.weakenByLoad = true;
    Random random(1);
    const FractureReport first = analyseFracture(heavy.bar, heavy.piece, heavy.loads, Eigen::Vector3d::Zero(), s, random);
    analyseFracture(light.bar, light.piece, light.loads, Eigen::Vector3d::Zero(), s, random);
    EXPECT_TRUE(first.broken.empty());
    int weakened = 0;
    for (const Link& l : heavy.bar.links()) weakened += l.strength < l.baseStrength;
    EXPECT_GT(weakened, 0);
    for (const Link& l : light.bar.links()) EXPECT_EQ(l.strength, l.baseStrength);
    // The weakened bar now breaks under the load it survived.
    const FractureReport second = analyseFracture(heavy.bar, heavy.piece, heavy.loads, Eigen::Vector3d::Zero(), s, random);
    EXPECT_FALSE(second.broken.empty());
}

TEST(DamageSpreading, WeakensAroundTheBreakDecayingWithDistance) {
    Lattice box(tetBox({1, 1, 1}, {6, 6, 6}), adobe());
    const int broken = box.linkCount() / 2;
    box.breakLink(broken);
    Random random(5);
    std::vector<int> removed;
    DamageSpreadingSettings s;
    spreadDamage(box, broken, s, 0.05, random, removed);
    const Eigen::Vector3d centre = box.links()[broken].faceCentre;
    double nearLoss = 0, farLoss = 0;
    int nearCount = 0, farCount = 0, touched = 0;
    for (const Link& l : box.links()) {
        if (l.broken) continue;
        const double loss = 1.0 - l.strength / l.baseStrength;
        touched += loss > 0;
        const double d = (l.faceCentre - centre).norm();
        if (d < 0.15) nearLoss += loss, ++nearCount;
        else if (d > 0.4) farLoss += loss, ++farCount;
    }
    EXPECT_GT(touched, 4);
    EXPECT_GT(nearLoss / nearCount, 0.05);
    EXPECT_EQ(farLoss, 0.0); // three steps of spreading never reach 0.4 m on 1/6 m cells
    (void)farCount;
}

TEST(DamageSpreading, SameSeedSameStrengthsOtherSeedOthers) {
    auto run = [](std::uint64_t seed) {
        Lattice box(tetBox({1, 1, 1}, {5, 5, 5}), adobe());
        Random random(seed);
        std::vector<int> removed;
        for (int k : {10, 200, 400}) {
            box.breakLink(k);
            spreadDamage(box, k, DamageSpreadingSettings{}, 0.05, random, removed);
        }
        std::vector<double> s;
        for (const Link& l : box.links()) s.push_back(l.strength);
        return s;
    };
    EXPECT_EQ(run(7), run(7));
    EXPECT_NE(run(7), run(8));
}

TEST(Noise, PerlinNoiseIsSeededBoundedAndSmooth) {
    const PerlinNoise a(1), b(1), c(2);
    double lo = 1e9, hi = -1e9;
    for (int i = 0; i < 2000; ++i) {
        const Eigen::Vector3d p(0.37 * i, 0.11 * i + 0.5, -0.23 * i);
        EXPECT_EQ(a(p), b(p));
        lo = std::min(lo, a(p));
        hi = std::max(hi, a(p));
        // Lipschitz: the gradient of improved noise is bounded (by about 3 per unit).
        EXPECT_LT(std::abs(a(p + Eigen::Vector3d(1e-4, 0, 0)) - a(p)), 4e-4);
    }
    EXPECT_GE(lo, -1.0);
    EXPECT_LE(hi, 1.0);
    EXPECT_LT(lo, -0.3);
    EXPECT_GT(hi, 0.3);
    EXPECT_EQ(a(Eigen::Vector3d(3, 4, 5)), 0.0); // zero on the integer grid
    EXPECT_NE(a(Eigen::Vector3d(3.3, 4.1, 5.7)), c(Eigen::Vector3d(3.3, 4.1, 5.7)));
}

TEST(Noise, StrengthsVaryAroundTheBaseAndRepeatForASeed) {
    NoiseSettings s;
    s.enabled = true;
    s.amplitude = 0.5;
    s.scale = 0.2;
    Lattice a(tetBox({1, 1, 0.2}, {10, 10, 2}), adobe()), b(tetBox({1, 1, 0.2}, {10, 10, 2}), adobe()),
        plain(tetBox({1, 1, 0.2}, {10, 10, 2}), adobe());
    applyNoise(a, s, 42);
    applyNoise(b, s, 42);
    double sum = 0, sum2 = 0;
    for (int k = 0; k < a.linkCount(); ++k) {
        EXPECT_EQ(a.links()[k].strength, b.links()[k].strength);
        const double f = a.links()[k].strength / plain.links()[k].strength;
        EXPECT_GE(f, s.floor);
        EXPECT_LE(f, 1.5 + 1e-12);
        sum += f;
        sum2 += f * f;
    }
    const double mean = sum / a.linkCount(), spread = std::sqrt(sum2 / a.linkCount() - mean * mean);
    EXPECT_NEAR(mean, 1.0, 0.1);
    EXPECT_GT(spread, 0.05);
}

} // namespace
} // namespace shatter::lattice
