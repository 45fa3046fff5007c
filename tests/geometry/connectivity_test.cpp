// The connectivity graph (source 000 §3.1): primitives are connected when they touch or
// overlap at rest, within the contact tolerance.
#include <shatter/plugin/geometry/Connectivity.h>
#include <shatter/plugin/geometry/PhysicalMesh.h>

#include "MeshFixtures.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <random>
#include <set>

using namespace shatter::geometry;
using shatter::test::FaceMesh;

namespace {

using PairSet = std::set<std::pair<int, int>>;

ConvexPolyhedron boxPrimitive(const Eigen::Vector3d& halfExtents, const Eigen::Isometry3d& pose) {
    FaceMesh m = shatter::test::closedBox(-halfExtents, halfExtents);
    shatter::test::transform(m, pose);
    return ConvexPolyhedron::create(m.positions, m.faces, {0, 1, 2, 3, 4, 5, 6, 7}, "box");
}

Eigen::Matrix3d rotationOf(const ConvexPolyhedron& box) {
    // Edges from vertex 0 along x (vertex 1), y (vertex 2), z (vertex 4) of closedBox.
    Eigen::Matrix3d r;
    r.col(0) = (box.vertices()[1] - box.vertices()[0]).normalized();
    r.col(1) = (box.vertices()[2] - box.vertices()[0]).normalized();
    r.col(2) = (box.vertices()[4] - box.vertices()[0]).normalized();
    return r;
}

// Exact separating-axis gap of two boxes: the largest gap between their projections over
// the 15 candidate axes. ≤ 0 means they overlap or touch; > 0 is a lower bound of their
// distance. Independent of libccd.
double separation(const ConvexPolyhedron& a, const ConvexPolyhedron& b) {
    const Eigen::Matrix3d ra = rotationOf(a), rb = rotationOf(b);
    std::vector<Eigen::Vector3d> axes;
    for (int i = 0; i < 3; ++i) {
        axes.push_back(ra.col(i));
        axes.push_back(rb.col(i));
        for (int j = 0; j < 3; ++j) {
            const Eigen::Vector3d c = ra.col(i).cross(rb.col(j));
            if (c.norm() > 1e-9) axes.push_back(c.normalized());
        }
    }
    double gap = -INFINITY;
    for (const auto& axis : axes) {
        double loA = INFINITY, hiA = -INFINITY, loB = INFINITY, hiB = -INFINITY;
        for (const auto& v : a.vertices()) {
            loA = std::min(loA, axis.dot(v));
            hiA = std::max(hiA, axis.dot(v));
        }
        for (const auto& v : b.vertices()) {
            loB = std::min(loB, axis.dot(v));
            hiB = std::max(hiB, axis.dot(v));
        }
        gap = std::max(gap, std::max(loB - hiA, loA - hiB));
    }
    return gap;
}

// Distance between segments p0p1 and q0q1 (closest points by clamped parameters).
double segmentDistance(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, const Eigen::Vector3d& q0,
                       const Eigen::Vector3d& q1) {
    const Eigen::Vector3d d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
    const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r), c = d1.dot(r), b = d1.dot(d2);
    const double denom = a * e - b * b;
    double s = denom > 1e-18 * a * e ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
    double t = (b * s + f) / e;
    if (t < 0.0) {
        t = 0.0;
        s = std::clamp(-c / a, 0.0, 1.0);
    } else if (t > 1.0) {
        t = 1.0;
        s = std::clamp((b - c) / a, 0.0, 1.0);
    }
    return ((p0 + s * d1) - (q0 + t * d2)).norm();
}

// Exact distance between two disjoint boxes: the closest points are either a vertex over
// the inside of a face or a pair of edges (vertex-edge and vertex-vertex are edge pairs).
double disjointBoxDistance(const ConvexPolyhedron& a, const ConvexPolyhedron& b) {
    double best = INFINITY;
    auto vertexOverFace = [&best](const ConvexPolyhedron& from, const ConvexPolyhedron& to) {
        for (size_t f = 0; f < to.faces().size(); ++f) {
            const Plane& plane = to.planes()[f];
            const auto& face = to.faces()[f];
            for (const auto& v : from.vertices()) {
                const Eigen::Vector3d q = v - plane.signedDistance(v) * plane.normal;
                bool inside = true;
                for (size_t k = 0; k < face.size(); ++k) {
                    const Eigen::Vector3d& e0 = to.vertices()[face[k]];
                    const Eigen::Vector3d& e1 = to.vertices()[face[(k + 1) % face.size()]];
                    inside = inside && (e1 - e0).cross(q - e0).dot(plane.normal) >= 0.0;
                }
                if (inside) best = std::min(best, std::abs(plane.signedDistance(v)));
            }
        }
    };
    vertexOverFace(a, b);
    vertexOverFace(b, a);
    for (int i = 0; i < 8; ++i)
        for (int bi = 1; bi < 8; bi <<= 1) {
            if (i & bi) continue;
            for (int j = 0; j < 8; ++j)
                for (int bj = 1; bj < 8; bj <<= 1) {
                    if (j & bj) continue;
                    best = std::min(best, segmentDistance(a.vertices()[i], a.vertices()[i | bi], b.vertices()[j],
                                                          b.vertices()[j | bj]));
                }
        }
    return best;
}

PairSet bruteForce(const std::vector<ConvexPolyhedron>& boxes, double tolerance) {
    PairSet pairs;
    for (int i = 0; i < int(boxes.size()); ++i)
        for (int j = i + 1; j < int(boxes.size()); ++j)
            if (withinTolerance(boxes[i], boxes[j], tolerance)) pairs.insert({i, j});
    return pairs;
}

// A 6×6×6 lattice of boxes 0.1 apart, each about 0.1 wide, randomly shifted (±4 mm),
// turned (±4°) and resized, so that many neighbours are near the contact threshold.
std::vector<ConvexPolyhedron> perturbedLattice(unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> shift(-0.004, 0.004), angle(-0.07, 0.07), size(0.046, 0.052);
    std::vector<ConvexPolyhedron> boxes;
    for (int i = 0; i < 6; ++i)
        for (int j = 0; j < 6; ++j)
            for (int k = 0; k < 6; ++k) {
                Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
                pose.translation() = 0.1 * Eigen::Vector3d(i, j, k) + Eigen::Vector3d(shift(rng), shift(rng), shift(rng));
                pose.linear() = (Eigen::AngleAxisd(angle(rng), Eigen::Vector3d::UnitX()) *
                                 Eigen::AngleAxisd(angle(rng), Eigen::Vector3d::UnitY()) *
                                 Eigen::AngleAxisd(angle(rng), Eigen::Vector3d::UnitZ()))
                                    .toRotationMatrix();
                boxes.push_back(boxPrimitive(Eigen::Vector3d(size(rng), size(rng), size(rng)), pose));
            }
    return boxes;
}

} // namespace

TEST(Connectivity, QuadGridConnectsExactlyEdgeAndCornerNeighbours) {
    const int nx = 7, ny = 5;
    const FaceMesh grid = shatter::test::quadGrid(nx, ny, 0.1);
    PhysicalMeshSettings s;
    s.thickness = 0.01;
    const PhysicalMesh mesh = buildPhysicalMesh("grid", grid.positions, grid.faces, s);
    ASSERT_EQ(int(mesh.primitives.size()), nx * ny);
    PairSet expected;
    for (int a = 0; a < nx * ny; ++a)
        for (int b = a + 1; b < nx * ny; ++b) {
            const int di = std::abs(a % nx - b % nx), dj = std::abs(a / nx - b / nx);
            // Edge neighbours share a side face; diagonal neighbours touch along an edge.
            if (std::max(di, dj) == 1) expected.insert({a, b});
        }
    const PairSet found(mesh.connections.begin(), mesh.connections.end());
    EXPECT_EQ(found, expected);
    EXPECT_EQ(found.size(), mesh.connections.size()); // each pair once
    EXPECT_TRUE(std::is_sorted(mesh.connections.begin(), mesh.connections.end()));
    EXPECT_EQ(mesh.componentCount(), 1);
}

TEST(Connectivity, CubesOneCentimetreApartAreNotConnected) {
    FaceMesh m = shatter::test::closedBox({0, 0, 0}, {0.1, 0.1, 0.1});
    shatter::test::append(m, shatter::test::closedBox({0.11, 0, 0}, {0.21, 0.1, 0.1}));
    const PhysicalMesh mesh = buildPhysicalMesh("two", m.positions, m.faces);
    ASSERT_EQ(mesh.primitives.size(), 2u);
    EXPECT_TRUE(mesh.connections.empty());
    EXPECT_EQ(mesh.componentCount(), 2);
}

TEST(Connectivity, ToleranceDecidesNearContacts) {
    const double tol = 1e-3;
    const Eigen::Vector3d h(0.5, 0.5, 0.5);
    const ConvexPolyhedron a = boxPrimitive(h, Eigen::Isometry3d::Identity());
    // b turned 45° about z: its vertical edge points at a's +x face.
    auto edgeOn = [&](double gap) {
        Eigen::Isometry3d pose = Eigen::Translation3d(0.5 + std::sqrt(0.5) + gap, 0, 0) *
                                 Eigen::AngleAxisd(std::numbers::pi / 4, Eigen::Vector3d::UnitZ());
        return boxPrimitive(h, pose);
    };
    auto faceOn = [&](double gap) { return boxPrimitive(h, Eigen::Isometry3d(Eigen::Translation3d(1.0 + gap, 0.2, 0))); };
    for (auto make : {std::function<ConvexPolyhedron(double)>(edgeOn), std::function<ConvexPolyhedron(double)>(faceOn)}) {
        EXPECT_TRUE(withinTolerance(a, make(-0.1), tol));    // overlap
        EXPECT_TRUE(withinTolerance(a, make(0.0), tol));     // contact
        EXPECT_TRUE(withinTolerance(a, make(0.9 * tol), tol));
        EXPECT_FALSE(withinTolerance(a, make(1.1 * tol), tol));
        EXPECT_FALSE(withinTolerance(a, make(0.3), tol));
    }
}

TEST(Connectivity, MatchesBruteForceAndSeparatingAxesOnAPerturbedLattice) {
    const std::vector<ConvexPolyhedron> boxes = perturbedLattice(2024);
    const double tol = 0.002;
    const auto pairs = touchingPairs(boxes, tol);
    const PairSet found(pairs.begin(), pairs.end());
    EXPECT_EQ(found.size(), pairs.size());
    EXPECT_EQ(found, bruteForce(boxes, tol));

    // Independent of libccd: overlapping boxes (no separating axis) must be connected,
    // boxes farther apart than the tolerance along a separating axis must not, and for the
    // near pairs in between the exact feature distance decides. Pairs within 1e-9 m of the
    // threshold are round-off territory and not judged.
    int overlapping = 0, apart = 0, nearIn = 0, nearOut = 0;
    for (int i = 0; i < int(boxes.size()); ++i)
        for (int j = i + 1; j < int(boxes.size()); ++j) {
            if ((boxes[i].bounds().center() - boxes[j].bounds().center()).norm() > 0.25) continue;
            const double gap = separation(boxes[i], boxes[j]);
            const bool connected = found.count({i, j}) > 0;
            if (gap <= 0.0) {
                ++overlapping;
                EXPECT_TRUE(connected) << i << " " << j << " gap " << gap;
            } else if (gap > tol) {
                ++apart;
                EXPECT_FALSE(connected) << i << " " << j << " gap " << gap;
            } else {
                const double distance = disjointBoxDistance(boxes[i], boxes[j]);
                if (std::abs(distance - tol) < 1e-9) continue;
                ++(distance <= tol ? nearIn : nearOut);
                EXPECT_EQ(connected, distance <= tol) << i << " " << j << " distance " << distance;
            }
        }
    // The layout really tests something: contacts, near misses either way, clear gaps.
    EXPECT_GT(overlapping, 100);
    EXPECT_GT(apart, 100);
    EXPECT_GT(nearIn, 20);
    EXPECT_GT(nearOut, 0);
}

TEST(Connectivity, RigidMotionOfTheWholeLayoutKeepsTheGraph) {
    std::vector<ConvexPolyhedron> boxes = perturbedLattice(99);
    const double tol = 0.002;
    const auto before = touchingPairs(boxes, tol);
    const Eigen::Isometry3d motion = Eigen::Translation3d(30, -12, 7) * Eigen::AngleAxisd(1.1, Eigen::Vector3d(2, -1, 1).normalized());
    for (auto& b : boxes) b = b.transformed(motion);
    const auto after = touchingPairs(boxes, tol);
    // Only pairs within round-off of the threshold could change; the lattice has none.
    EXPECT_EQ(after, before);
}

TEST(Connectivity, ComponentsOfAGraph) {
    EXPECT_EQ(countComponents(0, {}), 0);
    EXPECT_EQ(countComponents(5, {}), 5);
    EXPECT_EQ(countComponents(5, {{0, 1}, {3, 4}, {1, 0}}), 3);
    EXPECT_EQ(countComponents(5, {{0, 1}, {3, 4}, {1, 2}, {2, 3}}), 1);
}

TEST(Connectivity, PrimitivesTouchingAProbe) {
    const FaceMesh grid = shatter::test::quadGrid(4, 1, 1.0);
    PhysicalMeshSettings s;
    s.thickness = 0.1;
    const PhysicalMesh mesh = buildPhysicalMesh("row", grid.positions, grid.faces, s);
    // A small cube at the corner between cells 1 and 2, above the surface.
    const ConvexPolyhedron probe = boxPrimitive(Eigen::Vector3d(0.1, 0.1, 0.1), Eigen::Isometry3d(Eigen::Translation3d(2.0, 0.5, 0.05)));
    EXPECT_EQ(primitivesTouching(mesh.primitives, probe, 1e-4), (std::vector<int>{1, 2}));
}

// shareAnId on lists of every length up to 13 on either side, with one planted common id at
// every place and with disjoint lists: the four-at-a-time compares, the overlapping last four and the scalar
// path for fewer than four must all find it, and find nothing in disjoint lists.
TEST(Connectivity, ShareAnIdFindsACommonIdAtEveryPlace) {
    std::mt19937 random(7);
    auto distinct = [&](size_t n, int base) { // n distinct ids from base up, shuffled
        std::vector<int> ids(n);
        for (size_t k = 0; k < n; ++k) ids[k] = base + int(k) * 3;
        std::shuffle(ids.begin(), ids.end(), random);
        return ids;
    };
    for (size_t na = 0; na <= 13; ++na)
        for (size_t nb = 0; nb <= 13; ++nb) {
            const std::vector<int> a = distinct(na, 1), b = distinct(nb, 1000);
            EXPECT_FALSE(shareAnId(a, b)) << na << " " << nb;
            for (size_t i = 0; i < na; ++i)
                for (size_t k = 0; k < nb; ++k) {
                    std::vector<int> withCommon = b;
                    withCommon[k] = a[i];
                    EXPECT_TRUE(shareAnId(a, withCommon)) << na << " " << nb << " " << i << " " << k;
                    EXPECT_TRUE(shareAnId(withCommon, a)) << na << " " << nb << " " << i << " " << k;
                }
        }
}
