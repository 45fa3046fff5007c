// Tearing in place (MeshOpening.h) against the full recomputation (tearMesh and
// breakableConnections over the whole body): after every tear that leaves the body in one
// piece, the same primitives, connections, faces, tear edges and breakable connections, and
// the same vertices welded (ids numbered apart, compared through a canonical numbering).
#include <shatter/plugin/fracture/BreakableConnections.h>
#include <shatter/plugin/fracture/MeshOpening.h>
#include <shatter/plugin/fracture/Subdivision.h>
#include <shatter/plugin/fracture/Tearing.h>

#include "FractureFixtures.h"
#include "SheetFixture.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <random>

using namespace shatter;
using namespace shatter::fracture;
using shatter::test::sheetMesh;

namespace {

// Each id's number in the order the primitives' vertices first carry it: two meshes weld the
// same vertices when their slots read the same in these numbers.
std::map<int, int> canonicalIds(const geometry::PhysicalMesh& mesh) {
    std::map<int, int> out;
    for (const auto& p : mesh.primitives)
        for (int id : p.globalIds()) out.emplace(id, int(out.size()));
    return out;
}

void expectSameBody(const geometry::PhysicalMesh& opened, const geometry::PhysicalMesh& rebuilt) {
    ASSERT_EQ(opened.primitives.size(), rebuilt.primitives.size());
    EXPECT_EQ(opened.connections, rebuilt.connections);
    EXPECT_EQ(opened.sourceFace, rebuilt.sourceFace);
    EXPECT_EQ(opened.globalIdCount, rebuilt.globalIdCount);
    EXPECT_EQ(opened.visual.positions.size(), rebuilt.visual.positions.size());
    EXPECT_EQ(opened.mass.mass, rebuilt.mass.mass);
    const auto a = canonicalIds(opened), b = canonicalIds(rebuilt);
    const int visualA = int(opened.visual.positions.size()), visualB = int(rebuilt.visual.positions.size());
    for (size_t p = 0; p < opened.primitives.size(); ++p) {
        const auto& x = opened.primitives[p];
        const auto& y = rebuilt.primitives[p];
        EXPECT_EQ(x.vertices(), y.vertices());
        ASSERT_EQ(x.globalIds().size(), y.globalIds().size());
        for (size_t k = 0; k < x.globalIds().size(); ++k) {
            const int i = x.globalIds()[k], j = y.globalIds()[k];
            EXPECT_EQ(a.at(i), b.at(j)) << "primitive " << p << " vertex " << k;
            EXPECT_EQ(i < visualA, j < visualB) << "primitive " << p << " vertex " << k;
            if (i < visualA && j < visualB) {
                EXPECT_EQ(opened.visual.positions[size_t(i)], rebuilt.visual.positions[size_t(j)]);
            }
        }
    }
    ASSERT_EQ(opened.visual.faces.size(), rebuilt.visual.faces.size());
    for (size_t f = 0; f < opened.visual.faces.size(); ++f) {
        std::vector<int> x, y;
        for (int id : opened.visual.faces[f]) x.push_back(a.at(id));
        for (int id : rebuilt.visual.faces[f]) y.push_back(b.at(id));
        EXPECT_EQ(x, y) << "face " << f;
    }
    auto edges = [](const geometry::PhysicalMesh& m, const std::map<int, int>& canon) {
        std::vector<std::pair<int, int>> out;
        for (const auto& [u, v] : m.tearEdges)
            out.emplace_back(std::min(canon.at(u), canon.at(v)), std::max(canon.at(u), canon.at(v)));
        std::sort(out.begin(), out.end());
        return out;
    };
    EXPECT_EQ(edges(opened, a), edges(rebuilt, b));
}

// The same breakable connections with the same shared vertex pairs; `numberedAlike`: the two
// bodies number their ids alike, so the pairs come in the same order (sorted by id) too.
// Otherwise only the order differs, which the stretch test does not see (any pair too far
// apart breaks the connection).
void expectSameBreakable(std::vector<BreakableConnection> x, std::vector<BreakableConnection> y, bool numberedAlike) {
    ASSERT_EQ(x.size(), y.size());
    for (size_t k = 0; k < x.size(); ++k) {
        EXPECT_EQ(x[k].connection, y[k].connection);
        EXPECT_EQ(x[k].a, y[k].a);
        EXPECT_EQ(x[k].b, y[k].b);
        if (!numberedAlike) {
            std::sort(x[k].vertices.begin(), x[k].vertices.end());
            std::sort(y[k].vertices.begin(), y[k].vertices.end());
        }
        EXPECT_EQ(x[k].vertices, y[k].vertices);
    }
}

// Tears `body` step by step: each round breaks what `pick` chooses of its breakable
// connections; while the body holds together, the opened body equals the rebuilt one (both
// torn from the same state) and so does its breakable list.
struct Rounds {
    int opened = 0;   // rounds opened in place
    int idsSplit = 0; // over them
    int faces = 0;    // faces whose corners changed, over them
};
Rounds tearInRounds(geometry::PhysicalMesh body, bool everywhere, int rounds,
                 const std::function<std::vector<bool>(const geometry::PhysicalMesh&, const std::vector<BreakableConnection>&)>& pick) {
    std::vector<BreakableConnection> breakable = breakableConnections(body, everywhere);
    Rounds done;
    for (int round = 0; round < rounds; ++round) {
        const std::vector<bool> broken = pick(body, breakable);
        const TearResult rebuilt = tearMesh(body, broken);
        geometry::PhysicalMesh before = body;
        const std::optional<MeshOpening> opening = openMesh(body, broken);
        if (!opening) {
            EXPECT_GT(rebuilt.parts.size(), 1u) << "round " << round;
            EXPECT_EQ(body.connections, before.connections); // left as it was
            EXPECT_EQ(body.visual.faces, before.visual.faces);
            for (size_t p = 0; p < body.primitives.size(); ++p)
                EXPECT_EQ(body.primitives[p].globalIds(), before.primitives[p].globalIds());
            return done;
        }
        ++done.opened;
        done.idsSplit += opening->idsSplit;
        done.faces += int(opening->faces.size());
        EXPECT_EQ(rebuilt.parts.size(), 1u) << "round " << round;
        EXPECT_EQ(opening->idsSplit, rebuilt.idsSplit) << "round " << round;
        expectSameBody(body, rebuilt.parts[0]);
        updateBreakable(breakable, body, *opening, everywhere);
        expectSameBreakable(breakable, breakableConnections(body, everywhere), true);
        expectSameBreakable(breakable, breakableConnections(rebuilt.parts[0], everywhere), false);
        if (testing::Test::HasFailure()) return done;
    }
    return done;
}

// 12 rounds in which each breakable connection breaks with probability 1 / oneIn (seeded).
Rounds randomTearRounds(const geometry::PhysicalMesh& mesh, unsigned seed, unsigned oneIn) {
    std::mt19937 random(seed);
    return tearInRounds(mesh, true, 12, [&](const geometry::PhysicalMesh& body, const auto& breakable) {
        std::vector<bool> broken(body.connections.size(), false);
        for (const auto& c : breakable) broken[size_t(c.connection)] = random() % oneIn == 0;
        return broken;
    });
}

} // namespace

TEST(MeshOpening, ATearRunningDownItsLineEqualsTheFullRecomputationAtEveryStep) {
    // The line from the top edge to the bottom, torn a row at a time from the top: in place
    // while the bottom holds, then the halves part (openMesh leaves that to tearMesh).
    const geometry::PhysicalMesh sheet = sheetMesh({.column = 5, .from = 0, .to = 10});
    int row = 10;
    const Rounds rounds = tearInRounds(sheet, false, 20, [&](const geometry::PhysicalMesh& body, const auto& breakable) {
        std::vector<bool> broken(body.connections.size(), false);
        --row;
        for (const auto& c : breakable)
            for (int p : {c.a, c.b})
                if (body.primitives[size_t(p)].bounds().max.y() > 0.1 * row + 0.05) broken[size_t(c.connection)] = true;
        return broken;
    });
    EXPECT_EQ(rounds.opened, 9); // rows 9..1 open in place; the last row parts the halves
    EXPECT_EQ(rounds.idsSplit, 18); // rows 10..2 of the line's vertices and their inner copies
}

TEST(MeshOpening, RandomTearsEverywhereEqualTheFullRecomputation) {
    const Rounds rounds = randomTearRounds(sheetMesh({}), 5, 40);
    EXPECT_EQ(rounds.opened, 12);
    EXPECT_GT(rounds.idsSplit, 20);
    EXPECT_GT(rounds.faces, 10);
}

TEST(MeshOpening, SubdividedSheetWithTJunctionCornersEqualsTheFullRecomputation) {
    const geometry::PhysicalMesh sheet = test::sheetBody(4, 4, 0.25, 0.01);
    const Placement where{.point = {0.4, 0.55, 0.0}, .normal = {0.0, 0.0, -1.0}, .twist = seededTwist(3)};
    const SubdivisionResult cut = subdivideMesh(sheet, voronoiPattern({.cells = 32, .radius = 0.2}, 7), where, CutSettings{});
    const Rounds rounds = randomTearRounds(cut.mesh, 9, 30);
    EXPECT_EQ(rounds.opened, 12);
    EXPECT_GT(rounds.idsSplit, 20);
    EXPECT_GT(rounds.faces, 10);
}

TEST(MeshOpening, NothingBrokenChangesNothing) {
    geometry::PhysicalMesh sheet = sheetMesh({.column = 5, .from = 0, .to = 10});
    const geometry::PhysicalMesh before = sheet;
    const auto opening = openMesh(sheet, std::vector<bool>(sheet.connections.size(), false));
    ASSERT_TRUE(opening.has_value());
    EXPECT_EQ(opening->idsSplit, 0);
    EXPECT_TRUE(opening->faces.empty());
    EXPECT_EQ(sheet.connections, before.connections);
    EXPECT_EQ(sheet.visual.faces, before.visual.faces);
    EXPECT_EQ(sheet.tearEdges, before.tearEdges);
    for (size_t p = 0; p < sheet.primitives.size(); ++p)
        EXPECT_EQ(sheet.primitives[p].globalIds(), before.primitives[p].globalIds());
}

TEST(MeshOpening, BrokenFlagsMustMatchTheConnections) {
    geometry::PhysicalMesh sheet = sheetMesh({});
    try {
        openMesh(sheet, std::vector<bool>(3, true));
        FAIL() << "no error";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("body 'sheet': 3 broken flags for"), std::string::npos) << e.what();
    }
}
