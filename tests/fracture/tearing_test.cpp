// Breakable connections and tearing (source 000 §3.6) on a 10 × 10 quad sheet: which
// connections may break, when they do, and how the flood fill over shared global ids splits
// the ids and the parts so that the visual mesh opens exactly along the broken connections.
#include <shatter/plugin/common/InputError.h>
#include <shatter/plugin/fracture/BreakableConnections.h>
#include <shatter/plugin/fracture/Subdivision.h>
#include <shatter/plugin/fracture/Tearing.h>

#include "FractureFixtures.h"
#include "SheetFixture.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <random>
#include <set>

using namespace shatter;
using namespace shatter::fracture;
using shatter::test::SheetSpec;
using shatter::test::sheetMesh;

namespace {

constexpr double kSpacing = 0.1;

// The quad column (0..9) of a primitive of the sheet, from its centre.
int columnOf(const geometry::PhysicalMesh& mesh, int primitive) {
    const geometry::Aabb& box = mesh.primitives[size_t(primitive)].bounds();
    return int(std::floor(0.5 * (box.min.x() + box.max.x()) / kSpacing));
}

// Poses that move the primitives left of x = split by −gap/2 and the others by +gap/2 in x.
std::vector<Eigen::Isometry3d> pulledApart(const geometry::PhysicalMesh& mesh, int splitColumn, double gap) {
    std::vector<Eigen::Isometry3d> poses;
    for (int p = 0; p < int(mesh.primitives.size()); ++p) {
        Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
        pose.translation().x() = columnOf(mesh, p) < splitColumn ? -0.5 * gap : 0.5 * gap;
        poses.push_back(pose);
    }
    return poses;
}

std::vector<bool> flags(const geometry::PhysicalMesh& mesh, const std::vector<BreakableConnection>& breakable,
                        const std::vector<int>& which) {
    std::vector<bool> broken(mesh.connections.size(), false);
    for (int k : which) broken[size_t(breakable[size_t(k)].connection)] = true;
    return broken;
}

std::vector<int> all(const std::vector<BreakableConnection>& breakable) {
    std::vector<int> out(breakable.size());
    for (int k = 0; k < int(out.size()); ++k) out[size_t(k)] = k;
    return out;
}

using Edge = std::pair<int, int>;

// The undirected edges used by exactly one face: the open boundary of a visual mesh, written
// in the ids `toOriginal` maps its ids to.
std::multiset<Edge> boundaryEdges(const geometry::VisualMesh& visual, const std::vector<int>& toOriginal) {
    std::map<Edge, int> uses;
    for (const auto& face : visual.faces)
        for (size_t k = 0; k < face.size(); ++k) {
            const int a = face[k], b = face[(k + 1) % face.size()];
            ++uses[{std::min(a, b), std::max(a, b)}];
        }
    std::multiset<Edge> out;
    for (const auto& [edge, count] : uses) {
        const int a = toOriginal[size_t(edge.first)], b = toOriginal[size_t(edge.second)];
        if (count == 1) out.insert({std::min(a, b), std::max(a, b)});
    }
    return out;
}

std::vector<int> identity(int n) {
    std::vector<int> out;
    for (int i = 0; i < n; ++i) out.push_back(i);
    return out;
}

// The sheet's visual ids on vertex column 5 from row `from` to row `to`.
std::set<int> columnIds(const geometry::PhysicalMesh& mesh, int from, int to) {
    std::set<int> out;
    for (int v = 0; v < int(mesh.visual.positions.size()); ++v) {
        const Eigen::Vector3d& p = mesh.visual.positions[size_t(v)];
        const double row = p.y() / kSpacing;
        if (std::abs(p.x() - 5 * kSpacing) < 1e-9 && row > from - 1e-9 && row < to + 1e-9) out.insert(v);
    }
    return out;
}

} // namespace

TEST(BreakableConnections, TearLineMakesOnlyTheConnectionsAcrossItBreakable) {
    const geometry::PhysicalMesh sheet = sheetMesh({.column = 5, .from = 0, .to = 10});
    const auto breakable = breakableConnections(sheet, false);
    // 10 edge neighbours across x = 0.5 and 2 × 9 diagonal neighbours meeting on it.
    EXPECT_EQ(breakable.size(), 28u);
    for (const auto& c : breakable) {
        const int a = columnOf(sheet, c.a), b = columnOf(sheet, c.b);
        EXPECT_EQ(std::min(a, b), 4);
        EXPECT_EQ(std::max(a, b), 5);
        EXPECT_FALSE(c.vertices.empty());
    }
    // Everywhere: every connection of the sheet (all of them share a vertex).
    EXPECT_EQ(breakableConnections(sheet, true).size(), sheet.connections.size());
    // A sheet without tear lines has nothing to break unless everywhere.
    EXPECT_TRUE(breakableConnections(sheetMesh({}), false).empty());
}

TEST(BreakableConnections, NothingBreaksBelowTheDistance) {
    const geometry::PhysicalMesh sheet = sheetMesh({.column = 5, .from = 0, .to = 10});
    const double distance = 0.01;
    const auto breakable = breakableConnections(sheet, true);
    EXPECT_TRUE(stretchedConnections(breakable, sheet.primitives, pulledApart(sheet, 5, 0.99 * distance), distance).empty());
    // A rigid motion of the whole sheet stretches nothing.
    Eigen::Isometry3d moved = Eigen::Isometry3d::Identity();
    moved.rotate(Eigen::AngleAxisd(2.0, Eigen::Vector3d(1, 2, 3).normalized()));
    moved.translation() = Eigen::Vector3d(3, -1, 7);
    const std::vector<Eigen::Isometry3d> rigid(sheet.primitives.size(), moved);
    EXPECT_TRUE(stretchedConnections(breakable, sheet.primitives, rigid, 1e-9).empty());
    // Just past the distance, the 28 connections across the line break.
    EXPECT_EQ(stretchedConnections(breakable, sheet.primitives, pulledApart(sheet, 5, 1.01 * distance), distance).size(),
              28u);
}

TEST(BreakableConnections, OnlyTearLineConnectionsBreakWhereverTheSheetIsStretched) {
    const geometry::PhysicalMesh sheet = sheetMesh({.column = 5, .from = 0, .to = 10});
    // Every primitive shaken by up to 5 cm: far past the 1 cm distance everywhere.
    std::mt19937 random(7);
    std::uniform_real_distribution<double> offset(-0.05, 0.05);
    std::vector<Eigen::Isometry3d> poses;
    for (size_t p = 0; p < sheet.primitives.size(); ++p) {
        Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
        pose.translation() = Eigen::Vector3d(offset(random), offset(random), offset(random));
        poses.push_back(pose);
    }
    const auto lineOnly = breakableConnections(sheet, false);
    const auto stretched = stretchedConnections(lineOnly, sheet.primitives, poses, 0.01);
    EXPECT_FALSE(stretched.empty());
    for (int k : stretched) {
        const auto& c = lineOnly[size_t(k)];
        EXPECT_EQ(std::min(columnOf(sheet, c.a), columnOf(sheet, c.b)), 4);
        EXPECT_EQ(std::max(columnOf(sheet, c.a), columnOf(sheet, c.b)), 5);
    }
    const auto everywhere = breakableConnections(sheet, true);
    EXPECT_GT(stretchedConnections(everywhere, sheet.primitives, poses, 0.01).size(), 10 * stretched.size());
}

TEST(Tearing, SheetPulledApartAlongItsLineBecomesTwoPartsOf50) {
    const geometry::PhysicalMesh sheet = sheetMesh({.column = 5, .from = 0, .to = 10});
    const auto breakable = breakableConnections(sheet, false);
    const auto stretched = stretchedConnections(breakable, sheet.primitives, pulledApart(sheet, 5, 0.05), 0.01);
    const TearResult torn = tearMesh(sheet, flags(sheet, breakable, stretched));
    ASSERT_EQ(torn.parts.size(), 2u);
    double mass = 0.0;
    for (size_t k = 0; k < 2; ++k) {
        const geometry::PhysicalMesh& part = torn.parts[k];
        EXPECT_EQ(part.primitives.size(), 50u);
        EXPECT_EQ(part.componentCount(), 1);
        for (int p = 0; p < 50; ++p)
            EXPECT_EQ(columnOf(part, p) < 5, k == 0) << "part " << k << " primitive " << p;
        // Exact mass properties: the part's primitives summed.
        geometry::MassProperties sum;
        for (const auto& p : part.primitives) sum += p.massProperties(sheet.density);
        EXPECT_EQ(part.mass.mass, sum.mass);
        EXPECT_NEAR(part.mass.mass, 0.5 * sheet.mass.mass, 1e-12 * sheet.mass.mass);
        mass += part.mass.mass;
        EXPECT_EQ(part.visual.faces.size(), 50u);
    }
    EXPECT_NEAR(mass, sheet.mass.mass, 1e-12 * sheet.mass.mass);
    EXPECT_EQ(torn.parents[0].size() + torn.parents[1].size(), sheet.primitives.size());
}

TEST(Tearing, VisualBoundaryIsTheOriginalBoundaryPlusTheTornLineTwice) {
    const geometry::PhysicalMesh sheet = sheetMesh({.column = 5, .from = 0, .to = 10});
    const auto breakable = breakableConnections(sheet, false);
    const TearResult torn = tearMesh(sheet, flags(sheet, breakable, all(breakable)));
    std::multiset<Edge> expected = boundaryEdges(sheet.visual, identity(int(sheet.visual.positions.size())));
    EXPECT_EQ(expected.size(), 40u);
    for (const auto& [a, b] : sheet.tearEdges) expected.insert({a, b}), expected.insert({a, b});
    std::multiset<Edge> after;
    for (size_t k = 0; k < torn.parts.size(); ++k) {
        const auto edges = boundaryEdges(torn.parts[k].visual, torn.originalIds[k]);
        after.insert(edges.begin(), edges.end());
    }
    EXPECT_EQ(after, expected);
    EXPECT_EQ(after.size(), 60u);
}

TEST(Tearing, GlobalIdsSplitOnlyAlongTheTornLine) {
    const geometry::PhysicalMesh sheet = sheetMesh({.column = 5, .from = 0, .to = 10});
    const auto breakable = breakableConnections(sheet, false);
    const TearResult torn = tearMesh(sheet, flags(sheet, breakable, all(breakable)));
    std::map<int, int> copies; // body id -> how many part ids came from it
    for (const auto& ids : torn.originalIds)
        for (int id : ids) ++copies[id];
    const int visualCount = int(sheet.visual.positions.size());
    std::set<int> split;
    for (const auto& [id, n] : copies) {
        EXPECT_LE(n, 2);
        if (n > 1) split.insert(id < visualCount ? id : id - visualCount); // inner copies: visual id + count
    }
    EXPECT_EQ(split, columnIds(sheet, 0, 10));
    EXPECT_EQ(torn.idsSplit, 22); // 11 vertices on the line and their 11 inner copies
}

TEST(Tearing, SlitOpensInsideOneBodyAndTheTipStaysWelded) {
    // A tear line from the top edge to the middle: the sheet stays one part, opened along it.
    const geometry::PhysicalMesh sheet = sheetMesh({.column = 5, .from = 5, .to = 10});
    const auto breakable = breakableConnections(sheet, false);
    const TearResult torn = tearMesh(sheet, flags(sheet, breakable, all(breakable)));
    ASSERT_EQ(torn.parts.size(), 1u);
    EXPECT_EQ(torn.idsSplit, 10); // rows 6..10 of the column and their inner copies; the tip (row 5) stays
    std::set<int> split;
    std::map<int, int> copies;
    for (int id : torn.originalIds[0]) ++copies[id];
    for (const auto& [id, n] : copies)
        if (n > 1 && id < int(sheet.visual.positions.size())) split.insert(id);
    EXPECT_EQ(split, columnIds(sheet, 6, 10));
    std::multiset<Edge> expected = boundaryEdges(sheet.visual, identity(int(sheet.visual.positions.size())));
    for (const auto& [a, b] : sheet.tearEdges) expected.insert({a, b}), expected.insert({a, b});
    EXPECT_EQ(boundaryEdges(torn.parts[0].visual, torn.originalIds[0]), expected);
    // The part can tear on along what is left of the line: its tear edges are the slit's.
    EXPECT_EQ(torn.parts[0].tearEdges.size(), 10u);
}

TEST(Tearing, NothingBrokenGivesTheBodyBack) {
    const geometry::PhysicalMesh sheet = sheetMesh({.column = 5, .from = 0, .to = 10});
    const TearResult torn = tearMesh(sheet, std::vector<bool>(sheet.connections.size(), false));
    ASSERT_EQ(torn.parts.size(), 1u);
    EXPECT_EQ(torn.idsSplit, 0);
    EXPECT_EQ(torn.parts[0].connections, sheet.connections);
    EXPECT_EQ(torn.parts[0].visual.faces.size(), sheet.visual.faces.size());
    EXPECT_EQ(torn.parts[0].mass.mass, sheet.mass.mass);
}

TEST(Tearing, SameInputSameBits) {
    const geometry::PhysicalMesh sheet = sheetMesh({.column = 5, .from = 2, .to = 10});
    const auto everywhere = breakableConnections(sheet, true);
    // Every third connection of the sheet breaks.
    std::vector<int> some;
    for (int k = 0; k < int(everywhere.size()); k += 3) some.push_back(k);
    const TearResult a = tearMesh(sheet, flags(sheet, everywhere, some));
    const TearResult b = tearMesh(sheet, flags(sheet, everywhere, some));
    ASSERT_EQ(a.parts.size(), b.parts.size());
    EXPECT_EQ(a.originalIds, b.originalIds);
    EXPECT_EQ(a.parents, b.parents);
    for (size_t k = 0; k < a.parts.size(); ++k) {
        EXPECT_EQ(a.parts[k].visual.faces, b.parts[k].visual.faces);
        EXPECT_EQ(a.parts[k].connections, b.parts[k].connections);
        for (size_t p = 0; p < a.parts[k].primitives.size(); ++p)
            EXPECT_EQ(a.parts[k].primitives[p].globalIds(), b.parts[k].primitives[p].globalIds());
    }
}

// The overload that moves the body's primitives into the parts gives the parts the copying
// one gives, bit for bit (vertices, planes, ids, mass), and with bad flags moves nothing.
TEST(Tearing, MovedBodyTearsAsACopiedOne) {
    const geometry::PhysicalMesh sheet = sheetMesh({.column = 5, .from = 2, .to = 10});
    const auto everywhere = breakableConnections(sheet, true);
    std::vector<int> some;
    for (int k = 0; k < int(everywhere.size()); k += 3) some.push_back(k);
    const std::vector<bool> broken = flags(sheet, everywhere, some);
    const TearResult copied = tearMesh(sheet, broken);
    geometry::PhysicalMesh consumed = sheet;
    const TearResult moved = tearMesh(std::move(consumed), broken);
    ASSERT_GT(copied.parts.size(), 1u);
    ASSERT_EQ(moved.parts.size(), copied.parts.size());
    EXPECT_TRUE(consumed.primitives.empty()); // the largest part took its vector, compacted
    EXPECT_EQ(moved.parents, copied.parents);
    EXPECT_EQ(moved.originalIds, copied.originalIds);
    EXPECT_EQ(moved.idsSplit, copied.idsSplit);
    for (size_t k = 0; k < copied.parts.size(); ++k) {
        const geometry::PhysicalMesh& a = moved.parts[k];
        const geometry::PhysicalMesh& b = copied.parts[k];
        EXPECT_EQ(a.visual.faces, b.visual.faces);
        EXPECT_EQ(a.visual.positions, b.visual.positions);
        EXPECT_EQ(a.connections, b.connections);
        EXPECT_EQ(a.sourceFace, b.sourceFace);
        EXPECT_EQ(a.tearEdges, b.tearEdges);
        EXPECT_EQ(a.globalIdCount, b.globalIdCount);
        EXPECT_EQ(a.mass.mass, b.mass.mass);
        EXPECT_EQ(a.mass.centerOfMass, b.mass.centerOfMass);
        ASSERT_EQ(a.primitives.size(), b.primitives.size());
        for (size_t p = 0; p < a.primitives.size(); ++p) {
            EXPECT_EQ(a.primitives[p].globalIds(), b.primitives[p].globalIds());
            EXPECT_EQ(a.primitives[p].vertices(), b.primitives[p].vertices());
            EXPECT_EQ(a.primitives[p].faces(), b.primitives[p].faces());
            ASSERT_EQ(a.primitives[p].planes().size(), b.primitives[p].planes().size());
            for (size_t f = 0; f < a.primitives[p].planes().size(); ++f) {
                EXPECT_EQ(a.primitives[p].planes()[f].normal, b.primitives[p].planes()[f].normal);
                EXPECT_EQ(a.primitives[p].planes()[f].offset, b.primitives[p].planes()[f].offset);
            }
        }
    }
    geometry::PhysicalMesh kept = sheet;
    EXPECT_THROW(tearMesh(std::move(kept), std::vector<bool>(3, true)), InputError);
    ASSERT_EQ(kept.primitives.size(), sheet.primitives.size());
    for (size_t p = 0; p < sheet.primitives.size(); ++p)
        EXPECT_EQ(kept.primitives[p].vertices(), sheet.primitives[p].vertices());
}

TEST(Tearing, BrokenFlagsMustMatchTheConnections) {
    const geometry::PhysicalMesh sheet = sheetMesh({});
    try {
        tearMesh(sheet, std::vector<bool>(3, true));
        FAIL() << "no error";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("body 'sheet': 3 broken flags for"), std::string::npos) << e.what();
    }
}

// A subdivision (Subdivision.h) puts T-junction vertices into the faces of uncut primitives
// where finer pieces meet their edges; only the pieces carry them. Torn everywhere a
// connection can break, every face of every part still names only ids its part carries:
// such a corner takes the id of a piece still connected to the face's primitive, or, torn
// from all of them, leaves the face (it lies on the face's straight edge).
TEST(Tearing, SubdividedSheetTearsWithItsTJunctionCorners) {
    const geometry::PhysicalMesh sheet = test::sheetBody(4, 4, 0.25, 0.01);
    const Placement where{.point = {0.4, 0.55, 0.0}, .normal = {0.0, 0.0, -1.0}, .twist = seededTwist(3)};
    const SubdivisionResult cut = subdivideMesh(sheet, voronoiPattern({.cells = 32, .radius = 0.2}, 7), where, CutSettings{});
    const geometry::PhysicalMesh& body = cut.mesh;
    size_t corners = 0;
    for (const auto& f : body.visual.faces) corners += f.size();
    for (const bool everything : {false, true}) {
        const auto breakable = breakableConnections(body, true);
        const TearResult torn = tearMesh(body, flags(body, breakable, everything ? all(breakable) : std::vector<int>{}));
        size_t faces = 0, cornersAfter = 0;
        for (const auto& part : torn.parts) {
            std::set<int> carried;
            for (const auto& p : part.primitives) carried.insert(p.globalIds().begin(), p.globalIds().end());
            for (const auto& f : part.visual.faces) {
                EXPECT_GE(f.size(), 3u);
                for (int id : f) EXPECT_TRUE(carried.count(id)) << "id " << id << " on no primitive of its part";
                cornersAfter += f.size();
            }
            faces += part.visual.faces.size();
        }
        EXPECT_EQ(faces, body.visual.faces.size());
        if (!everything) {
            EXPECT_EQ(cornersAfter, corners); // nothing broken: every corner stays
        } else {
            EXPECT_LT(cornersAfter, corners); // some T-junction corners were torn off
            EXPECT_GT(torn.parts.size(), 10u);
        }
    }
}
