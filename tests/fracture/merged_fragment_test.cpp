// Fragments that small islands were merged into (mergeSmallIslands joins an island to the
// largest it touches, in any region): the part of the body holding most of the rest stays the
// rest, every fragment's mesh keeps the body's connections between its whole primitives, and
// mass and momenta are conserved.
#include "FractureFixtures.h"
#include "tests/support/PartsConserve.h"
#include "tests/support/TouchedConnections.h"

#include <shatter/plugin/fracture/FractureMesh.h>
#include <shatter/plugin/geometry/RigidState.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>

using namespace shatter;
using namespace shatter::fracture;

namespace {

Placement hitAt(double x, double y) {
    Placement at;
    at.point = {x, y, 0.0};
    at.normal = {0.0, 0.0, -1.0};
    return at;
}

CutSettings cutSettings(bool inPlace, double minimumPieceSize) {
    CutSettings s;
    s.remainderInPlace = inPlace;
    s.minimumPieceSize = minimumPieceSize;
    return s;
}

// The strip frac16f found the case on: 40 × 2 quads hit near one end, pieces below 4.5 cm
// merged. Cell 0's small fragment joins the large far part beyond it.
struct Strip {
    geometry::PhysicalMesh body = test::sheetBody(40, 2, 0.05, 0.01);
    FracturePattern pattern = voronoiPattern({.cells = 12, .radius = 0.35}, 5);
};

std::pair<int, int> ordered(int a, int b) { return {std::min(a, b), std::max(a, b)}; }

// Each fragment's connections between its unclipped primitives (as body primitive pairs) are
// the body's connections with both ends whole in it: the same count and pairs.
void expectWholeConnectionsKept(const geometry::PhysicalMesh& body, const FractureResult& cut) {
    for (size_t f = 0; f < cut.pieces.size(); ++f) {
        const geometry::PhysicalMesh& mesh = cut.pieces[f];
        const std::vector<int>& parents = cut.parents[f];
        ASSERT_EQ(mesh.primitives.size(), parents.size());
        std::vector<char> whole(body.primitives.size(), 0);
        for (size_t k = 0; k < parents.size(); ++k)
            if (!cut.clipped[f][k]) whole[size_t(parents[k])] = 1;
        std::vector<std::pair<int, int>> kept, expected;
        for (const auto& [a, b] : mesh.connections)
            if (!cut.clipped[f][size_t(a)] && !cut.clipped[f][size_t(b)])
                kept.push_back(ordered(parents[size_t(a)], parents[size_t(b)]));
        for (const auto& [a, b] : body.connections)
            if (whole[size_t(a)] && whole[size_t(b)]) expected.push_back(ordered(a, b));
        std::sort(kept.begin(), kept.end());
        std::sort(expected.begin(), expected.end());
        EXPECT_EQ(kept.size(), expected.size()) << "fragment " << f << " (cell " << cut.cells[f] << ")";
        EXPECT_EQ(kept, expected) << "fragment " << f << " (cell " << cut.cells[f] << ")";
    }
}

// The pairs of a fragment's primitives that come from one body primitive or from two connected
// ones and touch (both unclipped: by the body's connection; else within the body's contact
// tolerance, as findIslands and mergeSmallIslands judge it) but have no connection in its
// mesh. A later break finds the fragment's islands by its connections: a missing one can let
// a part fall off where nothing was cut between them.
int missingConnections(const geometry::PhysicalMesh& body, const FractureResult& cut) {
    int missing = 0;
    for (size_t f = 0; f < cut.pieces.size(); ++f) {
        const geometry::PhysicalMesh& mesh = cut.pieces[f];
        std::vector<std::vector<int>> ofParent(body.primitives.size());
        for (size_t k = 0; k < cut.parents[f].size(); ++k) ofParent[size_t(cut.parents[f][k])].push_back(int(k));
        std::vector<std::pair<int, int>> connected = mesh.connections;
        std::sort(connected.begin(), connected.end());
        auto touching = [&](int i, int j) {
            if (!cut.clipped[f][size_t(i)] && !cut.clipped[f][size_t(j)]) return true;
            const auto &a = mesh.primitives[size_t(i)], &b = mesh.primitives[size_t(j)];
            if (!a.bounds().inflated(body.contactTolerance).overlaps(b.bounds())) return false;
            const auto& ids = b.globalIds();
            return std::any_of(a.globalIds().begin(), a.globalIds().end(),
                               [&](int id) { return std::find(ids.begin(), ids.end(), id) != ids.end(); }) ||
                   geometry::withinTolerance(a, b, body.contactTolerance);
        };
        auto check = [&](int i, int j) {
            if (i != j && touching(i, j) && !std::binary_search(connected.begin(), connected.end(), ordered(i, j))) ++missing;
        };
        for (const auto& pieces : ofParent)
            for (size_t x = 0; x < pieces.size(); ++x)
                for (size_t y = x + 1; y < pieces.size(); ++y) check(pieces[x], pieces[y]);
        for (const auto& [a, b] : body.connections)
            for (int i : ofParent[size_t(a)])
                for (int j : ofParent[size_t(b)]) check(i, j);
    }
    return missing;
}

// Mass and momenta of the body moving and spinning are those of its fragments and its rest.
void expectConserved(const geometry::PhysicalMesh& body, const FractureResult& cut) {
    const geometry::RigidState whole =
        geometry::rigidState(body.mass, Eigen::Vector3d(0.3, -1.0, 0.5), Eigen::Vector3d(2.0, 1.0, -3.0));
    std::vector<geometry::RigidState> parts;
    for (const auto& mesh : cut.pieces) parts.push_back(geometry::partState(whole, mesh.mass));
    if (cut.remainderEdit) parts.push_back(geometry::partState(whole, cut.remainderEdit->mass));
    test::expectPartsConserveTheWhole(whole, parts);
}

// The volume of the rest (the edit's or the remainder fragment's) and the largest of the others.
std::pair<double, double> restAndLargestOther(const FractureResult& cut) {
    double rest = cut.remainderEdit ? cut.remainderEdit->mass.volume : 0.0, other = 0.0;
    for (size_t f = 0; f < cut.pieces.size(); ++f) {
        if (int(f) == cut.remainder) rest = cut.pieces[f].mass.volume;
        else other = std::max(other, cut.pieces[f].mass.volume);
    }
    return {rest, other};
}

} // namespace

TEST(MergedFragment, TheStripsLargePartStaysTheRestWhenASmallCellFragmentJoinsIt) {
    // Before, the merged island kept cell 0's region (its first piece's): the end's few quads
    // were the rest and the large part flew off as cell 0's fragment. Checked to be the case:
    // with small pieces loose, the cut makes more fragments (a merge happened), and the rest
    // is then the large far part too.
    const Strip strip;
    for (const double x : {0.33, 0.34, 0.35})
        for (const bool inPlace : {false, true}) {
            SCOPED_TRACE(testing::Message() << "x " << x << (inPlace ? " in place" : " rebuilt"));
            const FractureResult loose = fractureMesh(strip.body, strip.pattern, hitAt(x, 0.05), cutSettings(inPlace, 1e-4));
            const FractureResult merged = fractureMesh(strip.body, strip.pattern, hitAt(x, 0.05), cutSettings(inPlace, 0.045));
            EXPECT_GT(loose.pieces.size(), merged.pieces.size()) << "some small fragment was merged";
            const auto [rest, other] = restAndLargestOther(merged);
            EXPECT_GT(rest, 0.5 * strip.body.mass.volume) << "the rest is the strip's large part";
            EXPECT_GT(rest, other);
            if (inPlace) EXPECT_EQ(merged.remainder, -1);
            else {
                ASSERT_GE(merged.remainder, 0);
                EXPECT_EQ(merged.cells[size_t(merged.remainder)], -1);
            }
            expectConserved(strip.body, merged);
        }
}

TEST(MergedFragment, EveryFragmentKeepsTheBodyConnectionsBetweenItsWholePrimitives) {
    // The strip's merged cases, and a sheet hit in the middle and near its edge (far islands
    // cut off: far bodies), with small pieces loose and merged; rebuilt and in place. With 8
    // cells (seed 1), the strip hit at 0.9 (smallest 0.045) and the sheet at (0.35, 0.2)
    // (smallest 0.06) merge a small far island of connected whole quads into a cell's fragment
    // with no far body (asserted: so the rest's touched connections must list those of whole
    // far primitives no far body holds).
    const Strip strip;
    const geometry::PhysicalMesh sheet = test::sheetBody(30, 30, 0.05, 0.01);
    const FracturePattern sheetPattern = voronoiPattern({.cells = 24, .radius = 0.35}, 5);
    const FracturePattern eightCells = voronoiPattern({.cells = 8, .radius = 0.35}, 1);
    struct Hit {
        const geometry::PhysicalMesh* body;
        const FracturePattern* pattern;
        Placement where;
        double farIslandIntoACellAt = 0.0; // the smallest piece at which it is that case (0: none)
    };
    std::vector<Hit> hits;
    for (const double x : {0.33, 0.34, 0.35}) hits.push_back({&strip.body, &strip.pattern, hitAt(x, 0.05)});
    for (const double x : {0.75, 0.2}) hits.push_back({&sheet, &sheetPattern, hitAt(x, 0.75)});
    hits.push_back({&strip.body, &eightCells, hitAt(0.9, 0.05), 0.045});
    hits.push_back({&sheet, &eightCells, hitAt(0.35, 0.2), 0.06});
    for (const Hit& hit : hits) {
        const FractureResult loose = fractureMesh(*hit.body, *hit.pattern, hit.where, cutSettings(false, 1e-4));
        for (const double smallest : {1e-4, 0.045, 0.06})
            for (const bool inPlace : {false, true}) {
                SCOPED_TRACE(testing::Message() << "hit at " << hit.where.point.transpose() << ", smallest " << smallest
                                                << (inPlace ? ", in place" : ", rebuilt"));
                const FractureResult cut = fractureMesh(*hit.body, *hit.pattern, hit.where, cutSettings(inPlace, smallest));
                if (smallest == hit.farIslandIntoACellAt) {
                    ASSERT_TRUE(test::farIslandMergedIntoACell(*hit.body, loose, cut)) << "the case is still reached";
                }
                expectWholeConnectionsKept(*hit.body, cut);
                if (cut.remainderEdit) test::expectTouchedConnectionsComplete(*hit.body, *cut.remainderEdit);
                expectConserved(*hit.body, cut);
            }
    }
}

TEST(MergedFragment, EveryFragmentIsJoinedWhereverItsPartsTouch) {
    // Strips, sheets and boxes hit at many points by seeded patterns, small pieces merged: a
    // small island can merge into a neighbour that is then merged as small itself (island A
    // into B, then B into E). The contacts between A and E must be connected too, not only
    // B's own with E (until frac16h only those were, beyond whole primitives' connections):
    // every fragment is one island under its own connections, joined wherever two of its
    // parts touch, and the rest edited in place is one island.
    const geometry::PhysicalMesh strip = test::sheetBody(40, 2, 0.05, 0.01);
    const geometry::PhysicalMesh sheet = test::sheetBody(16, 16, 0.05, 0.01);
    std::vector<Eigen::Vector3i> cubes;
    for (int x = 0; x < 6; ++x)
        for (int y = 0; y < 6; ++y) cubes.emplace_back(x, y, 0);
    const geometry::PhysicalMesh boxes = test::cubeBody(cubes);
    struct Case {
        const geometry::PhysicalMesh* body;
        double scale, smallest;
        std::vector<Eigen::Vector2d> points;
    };
    std::vector<Case> cases{{&strip, 1.0, 0.045, {}}, {&sheet, 1.0, 0.045, {}}, {&boxes, 5.0, 0.75, {}}};
    for (int k = 0; k < 10; ++k) cases[0].points.emplace_back(0.1 + 0.2 * k, 0.05);
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) {
            cases[1].points.emplace_back(0.1 + 0.2 * i, 0.1 + 0.2 * j);
            if (i < 3 && j < 3) cases[2].points.emplace_back(0.5 + 2.5 * i, 0.5 + 2.5 * j);
        }
    int merges = 0;
    for (const Case& c : cases)
        for (const int cells : {8, 24})
            for (const std::uint64_t seed : {1, 2, 3}) {
                const FracturePattern pattern = voronoiPattern({.cells = cells, .radius = 0.35}, seed);
                for (const Eigen::Vector2d& point : c.points) {
                    SCOPED_TRACE(testing::Message() << c.body->primitives.size() << " primitives, " << cells << " cells, seed "
                                                    << seed << ", hit at " << point.transpose());
                    Placement where = hitAt(point.x(), point.y());
                    where.point.z() = c.body == &boxes ? 1.0 : 0.0;
                    where.scale = c.scale;
                    const FractureResult loose = fractureMesh(*c.body, pattern, where, cutSettings(false, 1e-4 * c.scale));
                    const FractureResult cut = fractureMesh(*c.body, pattern, where, cutSettings(false, c.smallest));
                    merges += loose.pieces.size() > cut.pieces.size();
                    for (const auto& mesh : cut.pieces) EXPECT_EQ(mesh.componentCount(), 1);
                    EXPECT_EQ(missingConnections(*c.body, cut), 0);
                    const FractureResult edited = fractureMesh(*c.body, pattern, where, cutSettings(true, c.smallest));
                    if (!edited.remainderEdit) continue;
                    geometry::PhysicalMesh rest = *c.body;
                    applyRemainderEdit(rest, *edited.remainderEdit);
                    EXPECT_EQ(rest.componentCount(), 1);
                }
            }
    EXPECT_GT(merges, 50) << "small pieces were merged in most cases";
}

namespace {

// Three slab cells across a bar of ten unit cubes along x: everything below x = cut, a thin
// slab [cut, cut + 0.2] and everything beyond. The slab's fragment (0.2 m³, in the cube the
// cut lies in) is below the minimum size and touches both others.
fracture::FracturePattern slabBetweenTwoCells(double cut) {
    fracture::FracturePattern p;
    const double big = 100.0;
    p.cells.push_back(test::boxPolyhedron({-big, -big, -big}, {cut, big, big}, 0));
    p.cells.push_back(test::boxPolyhedron({cut, -big, -big}, {cut + 0.2, big, big}, 0));
    p.cells.push_back(test::boxPolyhedron({cut + 0.2, -big, -big}, {big, big, big}, 0));
    p.centres = {{cut - 1.0, 0.0, 0.0}, {cut + 0.1, 0.0, 0.0}, {cut + 1.0, 0.0, 0.0}};
    p.radius = 1e3;
    fracture::finishPattern(p);
    return p;
}

std::vector<double> fragmentVolumes(const FractureResult& r) {
    std::vector<double> v;
    for (const auto& piece : r.pieces) v.push_back(piece.mass.volume);
    std::sort(v.begin(), v.end());
    return v;
}

} // namespace

TEST(MergedFragment, ASmallFragmentJoinsTheLargerByVolumeOfTheTwoItTouches) {
    // Which neighbour takes the small fragment, on a layout where the answer is known: the
    // one of more volume, on whichever side it lies (cuts at x = 6 and x = 3.3 put it on
    // either side). With small pieces loose, the slab is its own fragment.
    std::vector<Eigen::Vector3i> cubes;
    for (int x = 0; x < 10; ++x) cubes.push_back({x, 0, 0});
    const geometry::PhysicalMesh bar = test::cubeBody(cubes);
    const Placement at; // the pattern as given (identity placement)
    const double slab = 0.2, tol = 1e-9; // volumes of unit boxes cut by axis planes: rounding only
    for (const double cut : {6.0, 3.3}) {
        SCOPED_TRACE(testing::Message() << "cut at x = " << cut);
        const double below = cut, above = 10.0 - cut - slab;
        const auto pattern = slabBetweenTwoCells(cut);
        ASSERT_EQ(fractureMesh(bar, pattern, at, cutSettings(false, 1e-3)).pieces.size(), 3u) << "the slab loose";
        const auto merged = fractureMesh(bar, pattern, at, cutSettings(false, 0.7)); // 0.343 m³ > 0.2
        const std::vector<double> got = fragmentVolumes(merged);
        ASSERT_EQ(got.size(), 2u);
        EXPECT_NEAR(got[0], std::min(below, above), tol);
        EXPECT_NEAR(got[1], std::max(below, above) + slab, tol) << "the slab joined the larger neighbour";
        expectConserved(bar, merged);
    }
}

TEST(MergedFragment, ASmallFragmentJoinsTheNeighbourOfMoreVolumeNotOfMorePieces) {
    // largestOf sums the island of most pieces last and only until it exceeds the others: a
    // layout where that island has less volume. A row of unit cubes along x with a column of
    // nine more on the cube at x = 2. Cell A, a band [2.7, 3] across the column, holds ten thin
    // pieces (3 m³); cell B, beyond x = 3.2, seven pieces (6.8 m³); the slab [3, 3.2] between
    // them (0.2 m³) touches both. (From review56, which checked that joining the neighbour of
    // most pieces fails it.)
    std::vector<Eigen::Vector3i> cubes;
    for (int x = 0; x < 10; ++x) cubes.push_back({x, 0, 0});
    for (int y = 1; y < 10; ++y) cubes.push_back({2, y, 0});
    const geometry::PhysicalMesh body = test::cubeBody(cubes);
    const double big = 100.0;
    fracture::FracturePattern p;
    p.cells.push_back(test::boxPolyhedron({-big, -big, -big}, {2.7, big, big}, 0));
    p.cells.push_back(test::boxPolyhedron({2.7, -big, -big}, {3.0, big, big}, 0));
    p.cells.push_back(test::boxPolyhedron({3.0, -big, -big}, {3.2, big, big}, 0));
    p.cells.push_back(test::boxPolyhedron({3.2, -big, -big}, {big, big, big}, 0));
    p.centres = {{1.0, 0.0, 0.0}, {2.85, 0.0, 0.0}, {3.1, 0.0, 0.0}, {5.0, 0.0, 0.0}};
    p.radius = 1e3;
    fracture::finishPattern(p);
    const Placement at; // the pattern as given
    ASSERT_EQ(fractureMesh(body, p, at, cutSettings(false, 1e-3)).pieces.size(), 4u) << "the slab loose";
    const auto merged = fractureMesh(body, p, at, cutSettings(false, 0.7)); // 0.343 m³ > 0.2
    const std::vector<double> got = fragmentVolumes(merged);
    ASSERT_EQ(got.size(), 3u);
    EXPECT_NEAR(got[0], 3.0, 1e-9) << "the band of ten thin pieces kept its volume";
    EXPECT_NEAR(got[1], 7.0, 1e-9) << "the slab joined the neighbour of more volume";
    EXPECT_NEAR(got[2], 9.0, 1e-9);
    expectConserved(body, merged);
}
