// Loads on a lattice piece: gravity on the free particles, impacts on their nearest particles.
#include "LatticeFixtures.h"
#include <shatter/plugin/lattice/PieceLoads.h>
#include <shatter/plugin/lattice/TetGenerators.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <random>

namespace shatter::lattice {
namespace {

LatticePiece wholePiece(const Lattice& lattice) {
    return makePiece(lattice, test::indices(lattice.particleCount()));
}

Eigen::Vector3d total(const Eigen::VectorXd& loads) {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (int i = 0; i < loads.size() / 3; ++i) sum += loads.segment<3>(3 * i);
    return sum;
}

TEST(PieceLoads, GravityOnFreeParticlesAndEveryImpactAddUpToTheTotalForce) {
    Lattice lattice(tetBox({1.0, 0.5, 0.5}, {4, 2, 2}), glass());
    lattice.setFixed(0, true); // takes any load, carries none of its own
    LatticePiece piece = wholePiece(lattice);
    const Eigen::Vector3d g(0, -9.81, 0);
    const std::vector<Impact> impacts = {{{0.3, 0.1, 0.0}, {0, 2000, 50}, -1}, {{-0.4, 0.2, 0.1}, {-300, 0, 10}, 5}};
    const Eigen::VectorXd loads = pieceLoads(lattice, piece, g, impacts, 4);
    double freeMass = 0;
    for (int p = 1; p < lattice.particleCount(); ++p) freeMass += lattice.particles()[p].mass;
    const Eigen::Vector3d expected = freeMass * g + impacts[0].force + impacts[1].force;
    // Each impact's weights sum to one: the total is exact up to rounding.
    EXPECT_LT((total(loads) - expected).norm(), 1e-9 * expected.norm());
    EXPECT_EQ(loads.segment<3>(0), Eigen::Vector3d::Zero()); // the fixed particle (no impact near it)
}

TEST(PieceLoads, APointForceGoesMostlyToTheNearestParticle) {
    Eigen::VectorXd loads = Eigen::VectorXd::Zero(9);
    // Squared distances 0.01, 0.04, 0.09: weights ∝ 1/0.1, 1/0.2, 1/0.3 (softened by 1e-3 × 0.3).
    addPointForce({{0.01, 2}, {0.04, 0}, {0.09, 1}}, Eigen::Vector3d(6, 0, 0), loads);
    EXPECT_NEAR(loads[6] + loads[0] + loads[3], 6.0, 1e-12);
    EXPECT_GT(loads[6], loads[0]);
    EXPECT_GT(loads[0], loads[3]);
    EXPECT_NEAR(loads[6] / loads[0], (0.2 + 3e-4) / (0.1 + 3e-4), 1e-9); // inverse distance
}

TEST(PieceLoads, TheTouchedTetAndItsNeighboursAreTheNearestParticlesOfAContactOnIt) {
    // A contact on the surface of a tet: its own particle and its face neighbours are the
    // candidates. For a contact inside the tet the nearest particle found must be the tet itself,
    // as the grid search finds it.
    Lattice lattice(tetBox({1.0, 1.0, 1.0}, {3, 3, 3}), adobe());
    LatticePiece piece = wholePiece(lattice);
    std::mt19937 random(7);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    for (int trial = 0; trial < 50; ++trial) {
        const int tet = int(random() % piece.particles.size());
        const auto& t = lattice.mesh().tets[tet];
        // A random point inside the tet, near its centroid.
        Eigen::Vector3d point = lattice.particles()[tet].position;
        for (int c = 0; c < 4; ++c) point += 0.2 * unit(random) * (lattice.mesh().nodes[t[c]] - point);
        const auto byTet = nearestParticles(lattice, piece, point, tet, 4);
        const auto byGrid = nearestParticles(lattice, piece, point, -1, 1);
        ASSERT_FALSE(byTet.empty());
        EXPECT_EQ(byTet[0].second, byGrid[0].second);
        EXPECT_LE(byTet.size(), 4u);
        for (size_t k = 1; k < byTet.size(); ++k) EXPECT_LE(byTet[k - 1].first, byTet[k].first);
    }
}

// The touched tet's candidates in a piece that lacks some of the lattice's particles (none, a
// few, most): the tet and those of its face neighbours in the piece, found by a search of the
// whole list, sorted; the search over the places a neighbour can be finds the same.
TEST(PieceLoads, TheTouchedTetsNeighboursAreFoundInPiecesLackingParticles) {
    Lattice lattice(tetBox({1.0, 1.0, 1.0}, {4, 3, 3}), adobe());
    std::mt19937 random(11);
    for (double keep : {1.0, 0.97, 0.8, 0.5, 0.1}) {
        std::vector<int> particles;
        for (int p = 0; p < lattice.particleCount(); ++p)
            if (std::uniform_real_distribution<double>(0.0, 1.0)(random) < keep) particles.push_back(p);
        LatticePiece piece = makePiece(lattice, particles);
        for (int i = 0; i < int(particles.size()); ++i) {
            const Eigen::Vector3d point = lattice.particles()[particles[i]].position + Eigen::Vector3d(0.01, -0.02, 0.03);
            std::vector<std::pair<double, int>> expected = {{(lattice.particles()[particles[i]].position - point).squaredNorm(), i}};
            for (int n : lattice.faces().neighbour[particles[i]]) {
                const auto it = std::lower_bound(particles.begin(), particles.end(), n);
                if (n >= 0 && it != particles.end() && *it == n)
                    expected.emplace_back((lattice.particles()[n].position - point).squaredNorm(), int(it - particles.begin()));
            }
            std::sort(expected.begin(), expected.end());
            EXPECT_EQ(nearestParticles(lattice, piece, point, i, 5), expected) << "keep " << keep << ", particle " << i;
        }
    }
}

TEST(PieceLoads, KeptLoadsEqualFreshOnesBitForBitFromStepToStep) {
    // One piece through steps with changing impacts (some on the same particles, none, a
    // different g), each step's loads against those of a fresh piece: equal bit for bit.
    Lattice lattice(tetBox({1.0, 0.5, 0.5}, {4, 2, 2}), glass());
    lattice.setFixed(0, true);
    LatticePiece kept = wholePiece(lattice);
    const Eigen::Vector3d g(0, -9.81, 0), tilted(0.3, -9.8, 0.1);
    const std::vector<Impact> a = {{{0.3, 0.1, 0.0}, {0, 2000, 50}, -1}, {{-0.4, 0.2, 0.1}, {-300, 0, 10}, 5}};
    const std::vector<Impact> b = {{{-0.4, 0.2, 0.1}, {1e-3, -7, 0}, 5}, {{0.1, -0.2, 0.2}, {4, 5, 6}, 9},
                                   {{0.1, -0.2, 0.2}, {-4, 5, 6}, 9}};
    const std::vector<std::pair<Eigen::Vector3d, std::vector<Impact>>> steps = {
        {g, a}, {g, b}, {g, {}}, {g, a}, {tilted, b}, {tilted, b}, {g, {}}, {g, a}};
    for (size_t i = 0; i < steps.size(); ++i) {
        LatticePiece fresh = wholePiece(lattice);
        const Eigen::VectorXd expected = pieceLoads(lattice, fresh, steps[i].first, steps[i].second, 4);
        const Eigen::VectorXd& loads = pieceLoads(lattice, kept, steps[i].first, steps[i].second, 4);
        ASSERT_EQ(loads.size(), expected.size());
        EXPECT_EQ(std::memcmp(loads.data(), expected.data(), sizeof(double) * size_t(loads.size())), 0) << "step " << i;
    }
}

TEST(PieceLoads, OnlyChangesAboveTheFractionOfTheWeakestLinkCallForANewAnalysis) {
    Lattice lattice(tetBox({1.0, 0.5, 0.5}, {2, 1, 1}), adobe());
    LatticePiece piece = wholePiece(lattice);
    const Eigen::VectorXd loads = pieceLoads(lattice, piece, {0, -9.81, 0}, {}, 4);
    EXPECT_TRUE(loadsChanged(lattice, piece, loads, 0.1)); // never analysed
    piece.analysedLoads = loads;
    EXPECT_FALSE(loadsChanged(lattice, piece, loads, 0.1));
    double weakest = INFINITY;
    for (const Link& link : lattice.links()) weakest = std::min(weakest, link.strength);
    Eigen::VectorXd nudged = loads;
    nudged[1] += 0.05 * weakest; // below a tenth of any of particle 0's links
    EXPECT_FALSE(loadsChanged(lattice, piece, nudged, 0.1));
    nudged[1] += 10.0 * weakest;
    EXPECT_TRUE(loadsChanged(lattice, piece, nudged, 0.1));
}

} // namespace
} // namespace shatter::lattice
