#include "FractureFixtures.h"

#include <shatter/plugin/common/InputError.h>
#include <shatter/plugin/fracture/FracturePattern.h>

#include <gtest/gtest.h>

#include <cmath>

using namespace shatter;
using namespace shatter::fracture;

namespace {

double cellVolume(const FracturePattern& p) {
    double v = 0.0;
    for (const auto& c : p.cells) v += c.volume();
    return v;
}

bool sameBits(const FracturePattern& a, const FracturePattern& b) {
    if (a.cells.size() != b.cells.size()) return false;
    for (size_t i = 0; i < a.cells.size(); ++i)
        if (a.cells[i].vertices() != b.cells[i].vertices() || a.cells[i].faces() != b.cells[i].faces()) return false;
    return true;
}

// Every shared plane is used by cells on both sides or lies on the pattern's outer boundary;
// count the faces whose plane some other cell uses the other way round.
int sharedFaces(const FracturePattern& p) {
    std::map<int, std::set<double>> sides;
    for (const auto& faces : p.cellFaces)
        for (const auto& f : faces) sides[f.plane].insert(f.sign);
    int n = 0;
    for (const auto& faces : p.cellFaces)
        for (const auto& f : faces) n += sides[f.plane].size() == 2;
    return n;
}

} // namespace

TEST(VoronoiPattern, CellsTileTheirBoxAndTheSameSeedGivesTheSameBits) {
    VoronoiPatternSettings s;
    s.cells = 40;
    s.radius = 0.5;
    const FracturePattern a = voronoiPattern(s, 7);
    const FracturePattern b = voronoiPattern(s, 7);
    const FracturePattern c = voronoiPattern(s, 8);
    ASSERT_EQ(a.cells.size(), 40u);
    EXPECT_TRUE(sameBits(a, b));
    EXPECT_FALSE(sameBits(a, c));
    // The box is 4 × 1.5 × radius wide on each side: the cells fill it exactly.
    const double side = 4.0 * 1.5 * s.radius;
    EXPECT_NEAR(cellVolume(a), side * side * side, 1e-9 * side * side * side);
    // Every cell face but those on the box walls is shared with a neighbour (opposite sides).
    int boxFaces = 0, faces = 0;
    for (const auto& cell : a.cells)
        for (const auto& plane : cell.planes()) {
            ++faces;
            boxFaces += std::abs(std::abs(plane.offset) - 0.5 * side) < 1e-9 && plane.normal.cwiseAbs().maxCoeff() > 1 - 1e-12;
        }
    EXPECT_EQ(sharedFaces(a), faces - boxFaces);
}

TEST(VoronoiPattern, CellsAreSmallNearTheImpactAndLargeFarAway) {
    VoronoiPatternSettings s;
    s.cells = 200;
    s.radius = 1.0;
    s.biasExponent = 2.0;
    const FracturePattern p = voronoiPattern(s, 3);
    double nearVolume = 0.0, farVolume = 0.0;
    int nearCount = 0, farCount = 0;
    for (size_t i = 0; i < p.cells.size(); ++i) {
        const double r = p.centres[i].norm();
        if (r < 0.3) nearVolume += p.cells[i].volume(), ++nearCount;
        else if (r > 0.9 && r < 1.5) farVolume += p.cells[i].volume(), ++farCount;
    }
    ASSERT_GT(nearCount, 5);
    ASSERT_GT(farCount, 5);
    EXPECT_LT(nearVolume / nearCount * 10.0, farVolume / farCount);
}

TEST(GlassPattern, SectorsTimesRingsCoverTheOuterRingAndShareTheirFaces) {
    GlassPatternSettings s;
    s.sectors = 8;
    s.rings = 4;
    const FracturePattern a = glassPattern(s, 11);
    EXPECT_EQ(a.cells.size(), 32u);
    EXPECT_TRUE(sameBits(a, glassPattern(s, 11)));
    EXPECT_FALSE(sameBits(a, glassPattern(s, 12)));
    // Cells of ring k+1 lie outside those of ring k: the innermost are the smallest on average.
    double inner = 0.0, outer = 0.0;
    for (int i = 0; i < 8; ++i) inner += a.cells[size_t(i)].volume(), outer += a.cells[size_t(24 + i)].volume();
    EXPECT_LT(inner, outer);
    // Radial and ring faces between cells are shared: 8 sectors × (4 rings × 2 radial + 3 ring faces × 2).
    EXPECT_EQ(sharedFaces(a), 8 * (4 * 2 + 3 * 2));
    for (const auto& c : a.centres) EXPECT_LT(c.norm(), a.radius);
}

TEST(GridPattern, JitteredCellsFillTheGridBox) {
    GridPatternSettings s;
    s.count = 3;
    s.cellSize = 0.2;
    const FracturePattern p = gridPattern(s, 5);
    ASSERT_EQ(p.cells.size(), 27u);
    EXPECT_NEAR(cellVolume(p), std::pow(0.6, 3), 1e-12);
    EXPECT_TRUE(sameBits(p, gridPattern(s, 5)));
    for (const auto& c : p.centres) EXPECT_LE(c.norm(), p.radius);
}

TEST(PatternFile, ReadsOneCellPerObject) {
    const std::string text = test::objText(test::closedBox({0, 0, 0}, {1, 1, 1}), "a") +
                             test::objText(test::closedBox({1, 0, 0}, {2, 1, 1}), "b", 9);
    const FracturePattern p = loadPattern(test::writeTempFile("two_cells.obj", text));
    ASSERT_EQ(p.cells.size(), 2u);
    EXPECT_NEAR(p.cells[1].volume(), 1.0, 1e-12);
    EXPECT_EQ(sharedFaces(p), 2); // the face x = 1, once from each side
    EXPECT_GE(p.radius, p.centres[1].norm());
}

TEST(PatternFile, AnOpenOrNonConvexCellIsAnErrorNamingFileAndCell) {
    test::FaceMesh open = test::closedBox({0, 0, 0}, {1, 1, 1});
    open.faces.pop_back();
    const std::string openPath = test::writeTempFile("open_cell.obj", test::objText(open, "lid"));
    try {
        loadPattern(openPath);
        FAIL() << "an open cell was accepted";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find(openPath), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("'lid'"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("not closed"), std::string::npos) << e.what();
    }
    test::FaceMesh dented = test::closedBox({0, 0, 0}, {1, 1, 1});
    dented.positions[7] = {0.6, 0.6, 0.6}; // the (1,1,1) corner pushed inside
    const std::string dentPath = test::writeTempFile("dented_cell.obj", test::objText(dented, "dent"));
    try {
        loadPattern(dentPath);
        FAIL() << "a non-convex cell was accepted";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("'dent'"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("convex"), std::string::npos) << e.what();
    }
    EXPECT_THROW(loadPattern(test::writeTempFile("missing_dir/none.obj", "")), InputError);
}

TEST(PatternSettings, BadValuesAreErrors) {
    VoronoiPatternSettings v;
    v.cells = 0;
    EXPECT_THROW(voronoiPattern(v, 1), InputError);
    v = {};
    v.radius = 0.0;
    EXPECT_THROW(voronoiPattern(v, 1), InputError);
    GlassPatternSettings g;
    g.growth = 1.0;
    EXPECT_THROW(glassPattern(g, 1), InputError);
    GridPatternSettings d;
    d.cellSize = -1.0;
    EXPECT_THROW(gridPattern(d, 1), InputError);
    FracturePattern empty;
    empty.radius = 1.0;
    EXPECT_THROW(checkPattern(empty, "body 'x'"), InputError);
}

TEST(PatternDomain, VoronoiAndGridCellsHaveTheirBoxAsDomainHandMadeCellsNone) {
    // The domain's faces are shared planes, outward, on the box walls: 6 of them.
    auto expectBox = [](const FracturePattern& p, const geometry::Aabb& box) {
        ASSERT_EQ(p.domain.size(), 6u);
        for (const CellFace& f : p.domain) {
            const Eigen::Vector3d n = f.sign * p.planes[size_t(f.plane)].normal;
            const double d = f.sign * p.planes[size_t(f.plane)].offset;
            int axis = 0;
            EXPECT_NEAR(n.cwiseAbs().maxCoeff(&axis), 1.0, 1e-12);
            EXPECT_NEAR(d, n[axis] > 0 ? box.max[axis] : -box.min[axis], 1e-9);
            for (const auto& cell : p.cells) // every cell inside it
                for (const auto& v : cell.vertices()) EXPECT_LE(n.dot(v) - d, 1e-9);
        }
    };
    VoronoiPatternSettings v;
    v.cells = 24;
    v.radius = 1.0; // sites within 1.5, box of half-size 3
    expectBox(voronoiPattern(v, 9), geometry::Aabb{Eigen::Vector3d::Constant(-3.0), Eigen::Vector3d::Constant(3.0)});
    GridPatternSettings g;
    g.count = 2;
    g.cellSize = 0.5;
    expectBox(gridPattern(g, 4), geometry::Aabb{{-0.5, -0.5, -0.25}, {0.5, 0.5, 0.75}});
    // Cells set by hand: finishPattern knows no domain.
    EXPECT_TRUE(test::twoCells(0.5).domain.empty());
}
