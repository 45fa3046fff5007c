#include "FractureFixtures.h"

#include <shatter/plugin/common/InputError.h>
#include <shatter/plugin/fracture/Subdivision.h>

#include <gtest/gtest.h>

#include <cmath>

using namespace shatter;
using namespace shatter::fracture;

namespace {

// A 1 m × 1 m sheet of 4 × 4 quads (25 cm), 1 cm thick, hit off-centre from +z by a Voronoi
// pattern of 32 cells within 20 cm.
struct HitSheet {
    geometry::PhysicalMesh body = test::sheetBody(4, 4, 0.25, 0.01);
    FracturePattern pattern = voronoiPattern({.cells = 32, .radius = 0.2}, 7);
    Placement where{.point = {0.4, 0.55, 0.0}, .normal = {0.0, 0.0, -1.0}, .twist = seededTwist(3)};
    SubdivisionResult run() const { return subdivideMesh(body, pattern, where, CutSettings{}); }
};

double area(const geometry::VisualMesh& visual) {
    double a = 0.0;
    for (const auto& f : visual.faces) a += 0.5 * geometry::newellNormal(visual.positions, f).norm();
    return a;
}

// The edges used by one face only (no face uses them the other way), as segments.
std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> boundary(const geometry::VisualMesh& visual) {
    std::set<std::pair<int, int>> directed;
    for (const auto& f : visual.faces)
        for (size_t k = 0; k < f.size(); ++k) directed.emplace(f[k], f[(k + 1) % f.size()]);
    std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> out;
    for (const auto& [a, b] : directed)
        if (!directed.count({b, a})) out.emplace_back(visual.positions[size_t(a)], visual.positions[size_t(b)]);
    return out;
}

double length(const std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>>& segments) {
    double l = 0.0;
    for (const auto& [a, b] : segments) l += (b - a).norm();
    return l;
}

// Whether p lies on one of the segments (within `tolerance`).
bool onSegments(const Eigen::Vector3d& p, const std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>>& segments,
                double tolerance) {
    for (const auto& [a, b] : segments) {
        const Eigen::Vector3d e = b - a;
        const double t = std::clamp((p - a).dot(e) / e.squaredNorm(), 0.0, 1.0);
        if ((a + t * e - p).norm() <= tolerance) return true;
    }
    return false;
}

bool sameGeometry(const geometry::ConvexPolyhedron& a, const geometry::ConvexPolyhedron& b) {
    return a.vertices() == b.vertices() && a.faces() == b.faces();
}

} // namespace

TEST(Subdivision, KeepsVolumeMassAndCentreAndCutsOnlyNearTheHit) {
    HitSheet s;
    const SubdivisionResult r = s.run();
    ASSERT_GT(r.primitivesCut, 0);
    EXPECT_LT(r.primitivesCut, int(s.body.primitives.size()));
    EXPECT_GT(r.mesh.primitives.size(), 2 * s.body.primitives.size()); // finer where hit
    double volume = 0.0;
    for (const auto& p : r.mesh.primitives) volume += p.volume();
    EXPECT_LT(std::abs(volume - s.body.mass.volume) / s.body.mass.volume, 1e-9);
    EXPECT_LT(std::abs(r.mesh.mass.mass - s.body.mass.mass) / s.body.mass.mass, 1e-9);
    EXPECT_LT((r.mesh.mass.centerOfMass - s.body.mass.centerOfMass).norm(), 1e-9);
    EXPECT_LT((r.mesh.mass.inertia - s.body.mass.inertia).norm() / s.body.mass.inertia.norm(), 1e-9);
    // Every cut piece lies within the pattern's reach of the hit; the others are untouched.
    for (size_t i = 0; i < r.mesh.primitives.size(); ++i) {
        const int parent = r.parents[i];
        const bool near = (s.body.primitives[size_t(parent)].bounds().center() - s.where.point).norm() < 0.25 + 0.6;
        EXPECT_TRUE(near || !r.clipped[i]) << "primitive " << parent;
    }
}

TEST(Subdivision, PrimitivesNotCutAreTheBodysBitForBit) {
    HitSheet s;
    const SubdivisionResult r = s.run();
    int whole = 0;
    std::set<int> cutParents;
    for (size_t i = 0; i < r.mesh.primitives.size(); ++i) {
        if (r.clipped[i]) {
            cutParents.insert(r.parents[i]);
            continue;
        }
        ++whole;
        EXPECT_TRUE(sameGeometry(r.mesh.primitives[i], s.body.primitives[size_t(r.parents[i])]));
    }
    EXPECT_EQ(int(cutParents.size()), r.primitivesCut);
    EXPECT_EQ(whole + r.primitivesCut, int(s.body.primitives.size()));
    // The uncut primitives first, in the body's order, then the pieces by body primitive.
    ASSERT_EQ(r.kept, whole);
    EXPECT_TRUE(std::is_sorted(r.parents.begin(), r.parents.begin() + r.kept));
    EXPECT_TRUE(std::is_sorted(r.parents.begin() + r.kept, r.parents.end()));
    for (int i = 0; i < int(r.parents.size()); ++i) EXPECT_EQ(r.clipped[size_t(i)], i >= r.kept);
}

TEST(Subdivision, TheVisualSurfaceStaysInPlaceWithNoOpeningAndNoCrackFace) {
    HitSheet s;
    const SubdivisionResult r = s.run();
    const auto& before = s.body.visual;
    const auto& after = r.mesh.visual;
    ASSERT_GT(after.positions.size(), before.positions.size());
    // The body's visual vertices keep their ids and positions, bit for bit.
    for (size_t i = 0; i < before.positions.size(); ++i) EXPECT_EQ(after.positions[i], before.positions[i]);
    // New visual vertices lie on the sheet's surface (z = 0), inside it.
    for (size_t i = before.positions.size(); i < after.positions.size(); ++i) {
        EXPECT_NEAR(after.positions[i].z(), 0.0, 1e-12);
        EXPECT_GE(after.positions[i].x(), -1e-12);
        EXPECT_LE(after.positions[i].x(), 1.0 + 1e-12);
    }
    EXPECT_TRUE(std::none_of(after.crackFace.begin(), after.crackFace.end(), [](bool c) { return c; }));
    EXPECT_NEAR(area(after), area(before), 1e-12);
    // The open edges are the sheet's rim and nothing else: no T-junction, no gap.
    const auto rimBefore = boundary(before), rimAfter = boundary(after);
    EXPECT_NEAR(length(rimAfter), length(rimBefore), 1e-12);
    for (const auto& [a, b] : rimAfter) {
        EXPECT_TRUE(onSegments(a, rimBefore, 1e-12));
        EXPECT_TRUE(onSegments(b, rimBefore, 1e-12));
    }
    // Every primitive vertex with a visual id sits where the visual vertex is (welded at rest).
    for (const auto& p : r.mesh.primitives)
        for (size_t v = 0; v < p.vertices().size(); ++v) {
            const int id = p.globalIds()[v];
            if (id >= int(after.positions.size())) continue;
            EXPECT_LT((p.vertices()[v] - after.positions[size_t(id)]).norm(), 1e-9);
        }
}

TEST(Subdivision, ConnectionsKeepTheBodyOneComponentAndMatchTouchingPrimitives) {
    HitSheet s;
    const SubdivisionResult r = s.run();
    EXPECT_EQ(r.mesh.componentCount(), 1);
    // Among the pieces, the connections are exactly the touching pairs.
    const auto touching = geometry::touchingPairs(r.mesh.primitives, s.body.contactTolerance);
    std::set<std::pair<int, int>> expected, got(r.mesh.connections.begin(), r.mesh.connections.end());
    for (const auto& [a, b] : touching)
        if (r.clipped[size_t(a)] || r.clipped[size_t(b)]) expected.emplace(a, b);
    for (const auto& c : got)
        EXPECT_TRUE(expected.count(c) || !(r.clipped[size_t(c.first)] || r.clipped[size_t(c.second)]));
    for (const auto& c : expected) EXPECT_TRUE(got.count(c)) << c.first << "-" << c.second;
}

TEST(Subdivision, AClosedShellStaysClosedAndABoxRowKeepsItsSurface) {
    const auto ring = test::ringShellBody(0.1);
    ASSERT_TRUE(test::closedById(ring.visual.faces));
    const auto pattern = voronoiPattern({.cells = 24, .radius = 0.5}, 11);
    const Placement hit{.point = {2.0, 0.0, 0.5}, .normal = {0.0, 1.0, 0.0}, .twist = 0.3};
    const SubdivisionResult r = subdivideMesh(ring, pattern, hit, CutSettings{});
    ASSERT_GT(r.primitivesCut, 0);
    EXPECT_TRUE(test::closedById(r.mesh.visual.faces));
    EXPECT_NEAR(area(r.mesh.visual), area(ring.visual), 1e-9);
    EXPECT_EQ(r.mesh.componentCount(), ring.componentCount());

    // Closed convex parts (one primitive per box) cut through.
    const auto boxes = test::cubeBody({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}});
    const SubdivisionResult b =
        subdivideMesh(boxes, voronoiPattern({.cells = 16, .radius = 0.6}, 5),
                      Placement{.point = {1.5, 0.5, 1.0}, .normal = {0.0, 0.0, -1.0}}, CutSettings{});
    ASSERT_GT(b.primitivesCut, 0);
    EXPECT_TRUE(test::closedById(b.mesh.visual.faces));
    EXPECT_NEAR(area(b.mesh.visual), area(boxes.visual), 1e-9);
    EXPECT_NEAR(b.mesh.mass.volume, 3.0, 1e-12);
}

TEST(Subdivision, CrackFaceFlagsCarryOverAndNoneAreMade) {
    HitSheet s;
    EXPECT_TRUE(s.run().mesh.visual.crackFace.empty());
    s.body.visual.crackFace.assign(s.body.visual.faces.size(), false);
    s.body.visual.crackFace[9] = true; // the tile (1, 2), which the hit cuts
    const SubdivisionResult r = s.run();
    ASSERT_EQ(r.mesh.visual.crackFace.size(), r.mesh.visual.faces.size());
    double flagged = 0.0;
    for (size_t f = 0; f < r.mesh.visual.faces.size(); ++f)
        if (r.mesh.visual.isCrackFace(f)) flagged += 0.5 * geometry::newellNormal(r.mesh.visual.positions, r.mesh.visual.faces[f]).norm();
    EXPECT_NEAR(flagged, 0.25 * 0.25, 1e-12); // exactly that tile's area, however it was re-tiled
}

TEST(Subdivision, APatternThatCutsNothingLeavesTheBodyAsItIs) {
    HitSheet s;
    s.where.point = {5.0, 5.0, 0.0}; // far off the sheet
    const SubdivisionResult r = s.run();
    EXPECT_EQ(r.primitivesCut, 0);
    ASSERT_EQ(r.mesh.primitives.size(), s.body.primitives.size());
    for (size_t i = 0; i < r.mesh.primitives.size(); ++i) {
        EXPECT_TRUE(sameGeometry(r.mesh.primitives[i], s.body.primitives[i]));
        EXPECT_EQ(r.mesh.primitives[i].globalIds(), s.body.primitives[i].globalIds());
    }
    EXPECT_EQ(r.mesh.visual.faces, s.body.visual.faces);
}

TEST(Subdivision, SameInputGivesTheSameBits) {
    HitSheet s;
    const SubdivisionResult a = s.run(), b = s.run();
    ASSERT_EQ(a.mesh.primitives.size(), b.mesh.primitives.size());
    for (size_t i = 0; i < a.mesh.primitives.size(); ++i) {
        EXPECT_TRUE(sameGeometry(a.mesh.primitives[i], b.mesh.primitives[i]));
        EXPECT_EQ(a.mesh.primitives[i].globalIds(), b.mesh.primitives[i].globalIds());
    }
    EXPECT_EQ(a.mesh.visual.faces, b.mesh.visual.faces);
    EXPECT_EQ(a.mesh.visual.positions, b.mesh.visual.positions);
    EXPECT_EQ(a.mesh.connections, b.mesh.connections);
    EXPECT_EQ(a.parents, b.parents);
}

TEST(Subdivision, ASubdividedBodyCanBeSubdividedAgainElsewhere) {
    HitSheet s;
    const SubdivisionResult first = s.run();
    Placement second = s.where;
    second.point = {0.6, 0.45, 0.0}; // overlaps the first cut region
    const SubdivisionResult r = subdivideMesh(first.mesh, s.pattern, second, CutSettings{});
    ASSERT_GT(r.primitivesCut, 0);
    EXPECT_LT(std::abs(r.mesh.mass.volume - s.body.mass.volume) / s.body.mass.volume, 1e-9);
    EXPECT_EQ(r.mesh.componentCount(), 1);
    EXPECT_NEAR(area(r.mesh.visual), area(s.body.visual), 1e-12);
    EXPECT_NEAR(length(boundary(r.mesh.visual)), length(boundary(s.body.visual)), 1e-12);
    const auto rim = boundary(s.body.visual);
    for (const auto& [a, b] : boundary(r.mesh.visual))
        EXPECT_TRUE(onSegments(a, rim, 1e-12) && onSegments(b, rim, 1e-12)) << a.transpose() << " -> " << b.transpose();
}

TEST(Subdivision, BadInputNamesTheBody) {
    HitSheet s;
    s.where.normal = Eigen::Vector3d::Zero();
    try {
        s.run();
        FAIL() << "expected an error";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("sheet"), std::string::npos) << e.what();
    }
    HitSheet t;
    t.pattern.radius = 0.0;
    EXPECT_THROW(t.run(), InputError);
    HitSheet u;
    EXPECT_THROW(subdivideMesh(u.body, u.pattern, u.where, CutSettings{.snapTolerance = -1.0}), InputError);
}
