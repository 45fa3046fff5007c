// Fragments: components, exact mass properties, conservation of mass and momentum.
#include "LatticeFixtures.h"
#include <shatter/plugin/geometry/MassProperties.h>
#include <shatter/plugin/lattice/FractureAnalysis.h>
#include <shatter/plugin/geometry/RigidState.h>
#include <shatter/plugin/lattice/Fragments.h>
#include <shatter/plugin/lattice/TetGenerators.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace shatter::lattice {
namespace {

Lattice jittered() {
    GeneratorOptions o;
    o.jitter = 0.2;
    o.seed = 11;
    return Lattice(tetBox({0.9, 0.5, 0.4}, {6, 4, 3}, o), concrete());
}

TEST(Fragments, TetMassPropertiesAreExact) {
    const Lattice lattice = jittered();
    for (int t = 0; t < 20; ++t) {
        const Tet& tet = lattice.mesh().tets[t];
        const auto faces = outwardFaces(tet);
        std::vector<Eigen::Vector3d> v;
        for (int n : tet) v.push_back(lattice.mesh().nodes[n]);
        std::vector<std::vector<int>> f;
        for (const auto& face : faces) {
            std::vector<int> local;
            for (int n : face) local.push_back(int(std::find(tet.begin(), tet.end(), n) - tet.begin()));
            f.push_back(local);
        }
        const auto reference = geometry::polyhedronMassProperties(v, f, 2400.0);
        const auto mine = tetMassProperties(lattice.mesh(), tet, 2400.0);
        EXPECT_NEAR(mine.mass, reference.mass, 1e-12 * reference.mass);
        EXPECT_TRUE(mine.centerOfMass.isApprox(reference.centerOfMass, 1e-12));
        EXPECT_TRUE(mine.inertia.isApprox(reference.inertia, 1e-10)) << mine.inertia << "\n" << reference.inertia;
    }
}

TEST(Fragments, MassAndMomentumAreConservedThroughFragmentation) {
    Lattice lattice = jittered();
    // Break every third link (and a plane of links) so the body falls into many pieces,
    // single tets among them.
    for (int k = 0; k < lattice.linkCount(); ++k)
        if (k % 3 == 0 || std::abs(lattice.links()[k].faceCentre.x()) < 0.05) lattice.breakLink(k);
    const auto parts = connectedComponents(lattice, test::indices(lattice.particleCount()));
    ASSERT_GT(parts.size(), 10u);
    int singles = 0;
    for (const auto& p : parts) singles += p.size() == 1;
    EXPECT_GT(singles, 0); // single-tet fragments are kept
    // Parent: the whole body moving and spinning, placed off the origin.
    const auto whole = pieceMassProperties(lattice, test::indices(lattice.particleCount()));
    geometry::RigidState parent;
    parent.mass = whole.mass;
    parent.centre = whole.centerOfMass + Eigen::Vector3d(3.0, -1.0, 2.0);
    parent.inertia = whole.inertia;
    parent.velocity = Eigen::Vector3d(4.0, -2.5, 1.0);
    parent.angularVelocity = Eigen::Vector3d(-3.0, 7.0, 2.0);
    const Eigen::Vector3d shift(3.0, -1.0, 2.0);
    double mass = 0;
    Eigen::Vector3d p = Eigen::Vector3d::Zero(), l = Eigen::Vector3d::Zero();
    size_t tets = 0;
    for (const auto& part : parts) {
        auto m = pieceMassProperties(lattice, part);
        m.centerOfMass += shift;
        const geometry::RigidState s = geometry::partState(parent, m);
        mass += s.mass;
        p += s.linearMomentum();
        l += s.angularMomentum();
        tets += part.size();
    }
    EXPECT_EQ(tets, size_t(lattice.particleCount()));
    EXPECT_NEAR(mass, parent.mass, 1e-12 * parent.mass);
    EXPECT_LT((p - parent.linearMomentum()).norm(), 1e-9 * parent.linearMomentum().norm());
    EXPECT_LT((l - parent.angularMomentum()).norm(), 1e-9 * parent.angularMomentum().norm());
}

TEST(Fragments, PieceMassFromEachTetsKeptMassHasTheSameBits) {
    // A body keeps its tets' mass properties and sums them after each break: the sum must be the
    // one computed from the mesh, bit for bit (same seed => same bits downstream).
    const Lattice lattice = jittered();
    std::vector<geometry::MassProperties> tetMass;
    for (const Tet& tet : lattice.mesh().tets)
        tetMass.push_back(tetMassProperties(lattice.mesh(), tet, lattice.material().density));
    std::vector<int> part;
    for (int t = 0; t < lattice.particleCount(); t += 3) part.push_back(t);
    for (const auto& set : {test::indices(lattice.particleCount()), part}) {
        const auto fromMesh = pieceMassProperties(lattice, set);
        const auto fromKept = pieceMassProperties(tetMass, set);
        EXPECT_EQ(fromKept.mass, fromMesh.mass);
        EXPECT_EQ(fromKept.volume, fromMesh.volume);
        EXPECT_EQ(fromKept.centerOfMass, fromMesh.centerOfMass);
        EXPECT_EQ(fromKept.inertia, fromMesh.inertia);
    }
}

TEST(Fragments, SurfaceOfAnUnsortedListIsThatOfTheSortedOne) {
    const Lattice lattice(tetBox({1, 1, 1}, {3, 3, 3}), glass());
    std::vector<int> part;
    for (int t = lattice.particleCount() - 1; t >= 0; t -= 2) part.push_back(t); // descending
    std::vector<int> sorted = part;
    std::sort(sorted.begin(), sorted.end());
    const auto faces = surfaceFaces(lattice, part);
    EXPECT_FALSE(faces.empty());
    EXPECT_EQ(faces, surfaceFaces(lattice, sorted));
}

TEST(Fragments, SurfaceIsTheOuterFacesPlusBothSidesOfTheCracks) {
    Lattice lattice(tetBox({1, 1, 1}, {4, 4, 4}), glass());
    const auto whole = surfaceFaces(lattice, test::indices(lattice.particleCount()));
    EXPECT_EQ(int(whole.size()), lattice.faces().boundaryCount);
    int crack = 0;
    for (int k = 0; k < lattice.linkCount(); ++k)
        if (std::abs(lattice.links()[k].faceCentre.y()) < 1e-12) { // the plane y = 0 between cell layers
            lattice.breakLink(k);
            ++crack;
        }
    const auto parts = connectedComponents(lattice, test::indices(lattice.particleCount()));
    ASSERT_EQ(parts.size(), 2u);
    EXPECT_EQ(crack, 2 * 16);
    size_t faces = 0;
    for (const auto& part : parts) faces += surfaceFaces(lattice, part).size();
    EXPECT_EQ(int(faces), lattice.faces().boundaryCount + 2 * crack);
}

TEST(Fragments, ConvexityOfPieces) {
    // A 2 × 2 × 1 box of unit cells (6 tets each), centred at the origin.
    const Lattice lattice(tetBox({2, 2, 1}, {2, 2, 1}), adobe());
    std::vector<int> cell, lShape;
    for (int t = 0; t < lattice.particleCount(); ++t) {
        const Eigen::Vector3d& c = lattice.particles()[t].position;
        if (c.x() < 0 && c.y() < 0) cell.push_back(t);
        if (!(c.x() > 0 && c.y() > 0)) lShape.push_back(t); // three cells: an L
    }
    ASSERT_EQ(cell.size(), 6u);
    ASSERT_EQ(lShape.size(), 18u);
    // A tet, a cell and the whole box are convex (to rounding); the L's inner corner node lies
    // a whole cell in front of the faces of the missing cell's neighbours.
    EXPECT_LT(convexityDefect(lattice, {cell[0]}), 1e-12);
    EXPECT_LT(convexityDefect(lattice, cell), 1e-12);
    EXPECT_LT(convexityDefect(lattice, test::indices(lattice.particleCount())), 1e-12);
    EXPECT_NEAR(convexityDefect(lattice, lShape), 1.0, 1e-12);
    EXPECT_TRUE(isConvexPiece(lattice, {cell[0]}, 0.02, 64));
    EXPECT_TRUE(isConvexPiece(lattice, cell, 0.02, 64));
    EXPECT_TRUE(isConvexPiece(lattice, test::indices(lattice.particleCount()), 0.02, 64));
    EXPECT_FALSE(isConvexPiece(lattice, lShape, 0.02, 64));
    EXPECT_FALSE(isConvexPiece(lattice, test::indices(lattice.particleCount()), 0.02, 23)); // too many tets to test
    EXPECT_TRUE(isConvexPiece(lattice, lShape, 0.7, 64)); // the defect is 1 / cbrt(3) = 0.69 of its cube root
}

TEST(Fragments, APiecesSizeIsTheDiameterAboutItsCentreOfMassThatHoldsItsNodes) {
    // A 2 × 2 × 1 box of unit cells, centred at the origin: a cell's nodes are its 8 corners,
    // √3/2 from its centre; the whole box's are up to √(1 + 1 + 1/4) from the origin.
    const Lattice lattice(tetBox({2, 2, 1}, {2, 2, 1}), adobe());
    std::vector<int> cell;
    for (int t = 0; t < lattice.particleCount(); ++t)
        if (lattice.particles()[t].position.x() < 0 && lattice.particles()[t].position.y() < 0) cell.push_back(t);
    const Eigen::Vector3d centre = pieceMassProperties(lattice, cell).centerOfMass;
    EXPECT_NEAR(pieceSize(lattice, cell, centre), std::sqrt(3.0), 1e-12);
    EXPECT_NEAR(pieceSize(lattice, test::indices(lattice.particleCount()), Eigen::Vector3d::Zero()), 2 * std::sqrt(2.25), 1e-12);
    // About another point, the farthest node is farther.
    EXPECT_GT(pieceSize(lattice, cell, centre + Eigen::Vector3d(0.1, 0, 0)), std::sqrt(3.0));
}

TEST(Fragments, TwoTetsAcrossAJitteredFaceAreConvexOnlyWhenTheirApexesSeeTheFace) {
    // Two tets sharing a face form a bipyramid, convex exactly when the segment between their
    // free corners crosses the shared triangle.
    const Lattice lattice = jittered();
    int convex = 0, concave = 0;
    for (const Link& l : lattice.links()) {
        const auto& nodes = lattice.mesh().nodes;
        auto apex = [&](int t) {
            for (int n : lattice.mesh().tets[t])
                if (std::find(l.face.begin(), l.face.end(), n) == l.face.end()) return nodes[n];
            return Eigen::Vector3d(Eigen::Vector3d::Zero());
        };
        const Eigen::Vector3d p = apex(l.a), q = apex(l.b);
        const Eigen::Vector3d a = nodes[l.face[0]], b = nodes[l.face[1]], c = nodes[l.face[2]];
        // Barycentric coordinates of where pq meets the face's plane.
        const Eigen::Vector3d n = (b - a).cross(c - a);
        const double s = n.dot(a - p) / n.dot(q - p);
        const Eigen::Vector3d x = p + s * (q - p);
        const double wa = n.dot((b - x).cross(c - x)), wb = n.dot((c - x).cross(a - x)), wc = n.dot((a - x).cross(b - x));
        const bool crosses = std::min({wa, wb, wc}) > 0;
        const double defect = convexityDefect(lattice, {l.a, l.b});
        if (crosses) {
            EXPECT_LT(defect, 1e-12);
            ++convex;
        } else if (std::min({wa, wb, wc}) < -1e-6 * n.squaredNorm()) {
            EXPECT_GT(defect, 0.0);
            ++concave;
        }
    }
    EXPECT_GT(convex, 10);
    EXPECT_GT(concave, 10);
}

TEST(Fragments, SameSeedGivesIdenticalFragments) {
    auto shatter = [](std::uint64_t seed) {
        Lattice wall(tetBox({1.0, 0.8, 0.2}, {10, 8, 2}), adobe());
        for (int t : tetsWithFaceOnPlane(wall.mesh(), {0, 1, 0}, -0.4, 1e-9)) wall.setFixed(t, true);
        LatticePiece piece = makePiece(wall, test::indices(wall.particleCount()));
        Eigen::VectorXd loads = Eigen::VectorXd::Zero(3 * wall.particleCount());
        for (int i = 0; i < wall.particleCount(); ++i)
            if ((wall.particles()[i].position - Eigen::Vector3d(0, 0.1, 0.1)).norm() < 0.12) loads[3 * i + 2] = -2e4;
        Random random(seed);
        analyseFracture(wall, piece, loads, Eigen::Vector3d::Zero(), FractureAnalysisSettings{}, random);
        return connectedComponents(wall, piece.particles);
    };
    const auto a = shatter(3), b = shatter(3);
    EXPECT_GT(a.size(), 3u);
    EXPECT_EQ(a, b);
}

} // namespace
} // namespace shatter::lattice
