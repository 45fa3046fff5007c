// Limits of the physical-mesh builder. PhysicalMeshSettings::maxPrimitives: a mesh or file that
// would make more primitives is an error before they are built, giving the count, a memory
// estimate and how to raise it. Sizes: coordinates beyond 1e12 m and bodies under a nanometre
// across are errors (their volume integrals would overflow or vanish).
#include <shatter/plugin/common/InputError.h>
#include <shatter/plugin/geometry/ObjFile.h>
#include <shatter/plugin/geometry/PhysicalMesh.h>

#include "MeshFixtures.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace shatter::geometry;
using shatter::test::FaceMesh;

namespace {

// The message of the InputError `build` throws ("" when it throws none).
template <class Build>
std::string errorOf(const Build& build) {
    try {
        build();
    } catch (const shatter::InputError& e) {
        return e.what();
    }
    return "";
}

} // namespace

TEST(PrimitiveLimit, AMeshOfMorePrimitivesThanTheLimitIsRefusedNamingCountMemoryAndOption) {
    const FaceMesh grid = shatter::test::quadGrid(10, 10, 0.1); // 100 flat quads: 100 prisms
    PhysicalMeshSettings s;
    s.maxPrimitives = 100;
    EXPECT_EQ(buildPhysicalMesh("grid", grid.positions, grid.faces, s).primitives.size(), 100u);
    s.maxPrimitives = 99;
    const std::string what = errorOf([&] { buildPhysicalMesh("grid", grid.positions, grid.faces, s); });
    EXPECT_NE(what.find("body 'grid'"), std::string::npos) << what;
    EXPECT_NE(what.find("100 primitives"), std::string::npos) << what;
    EXPECT_NE(what.find(" MB"), std::string::npos) << what;
    EXPECT_NE(what.find("limit of 99"), std::string::npos) << what;
    EXPECT_NE(what.find("--max-primitives"), std::string::npos) << what;
}

TEST(PrimitiveLimit, CountsTheTrianglesOfSplitFacesAndOneForAClosedConvexPart) {
    // An L-shaped hexagon (not convex: 4 triangles) and a closed box (1 primitive).
    FaceMesh m;
    m.positions = {{0, 0, 0}, {2, 0, 0}, {2, 1, 0}, {1, 1, 0}, {1, 2, 0}, {0, 2, 0}};
    m.faces = {{0, 1, 2, 3, 4, 5}};
    shatter::test::append(m, shatter::test::closedBox({3, 0, 0}, {4, 1, 1}));
    PhysicalMeshSettings s;
    s.maxPrimitives = 5;
    EXPECT_EQ(buildPhysicalMesh("l", m.positions, m.faces, s).primitives.size(), 5u);
    s.maxPrimitives = 4;
    EXPECT_NE(errorOf([&] { buildPhysicalMesh("l", m.positions, m.faces, s); }).find("5 primitives"),
              std::string::npos);
}

TEST(PrimitiveLimit, AFileCountsAllItsBodiesTogether) {
    const FaceMesh grid = shatter::test::quadGrid(6, 10, 0.1); // 60 prisms each
    std::string text = shatter::test::objText(grid, "a");
    text += shatter::test::objText(grid, "b", int(grid.positions.size()) + 1);
    const ObjFile file = parseObj(text, "two.obj");
    PhysicalMeshSettings s;
    s.maxPrimitives = 120;
    EXPECT_EQ(buildPhysicalObject(file, s).bodies.size(), 2u);
    s.maxPrimitives = 119;
    const std::string what = errorOf([&] { buildPhysicalObject(file, s); });
    EXPECT_NE(what.find("body 'b'"), std::string::npos) << what;
    EXPECT_NE(what.find("120 with the file's earlier bodies"), std::string::npos) << what;
}

TEST(PrimitiveLimit, TheDefaultRefusesTwoHundredThousandFaces) {
    const FaceMesh grid = shatter::test::quadGrid(450, 450, 0.01);
    const std::string what = errorOf([&] { buildPhysicalMesh("scan", grid.positions, grid.faces); });
    EXPECT_NE(what.find("202500 primitives"), std::string::npos) << what;
    EXPECT_NE(what.find("limit of 200000"), std::string::npos) << what;
    PhysicalMeshSettings s;
    s.maxPrimitives = 0;
    EXPECT_NE(errorOf([&] { buildPhysicalMesh("g", grid.positions, grid.faces, s); }).find("maxPrimitives must be >= 1"),
              std::string::npos);
}

TEST(MeshSize, CoordinatesBeyondATerametreAndBodiesUnderANanometreAreErrors) {
    // At 1e100 m an L-shaped prism's area vectors overflowed and it passed as one convex part;
    // at 1e110 m its mass came out 0.
    for (double scale : {1e13, 1e100, 1e110}) {
        FaceMesh box = shatter::test::closedBox({0, 0, 0}, {1, 1, 1});
        for (auto& p : box.positions) p *= scale;
        const std::string what = errorOf([&] { buildPhysicalMesh("far", box.positions, box.faces); });
        EXPECT_NE(what.find("body 'far': face 0: vertex 2 has a coordinate of"), std::string::npos) << what;
        EXPECT_NE(what.find("beyond the 1e+12 m the geometry handles (check units and scale)"), std::string::npos) << what;
    }
    FaceMesh tiny = shatter::test::closedBox({0, 0, 0}, {1e-10, 1e-10, 1e-10});
    const std::string what = errorOf([&] { buildPhysicalMesh("dust", tiny.positions, tiny.faces); });
    EXPECT_NE(what.find("body 'dust': is 1.73205e-10 m across, below the 1e-09 m"), std::string::npos) << what;
    // Within range: a metre box a terametre out, a micrometre box.
    FaceMesh far = shatter::test::closedBox({1e12 - 1, 0, 0}, {1e12, 1, 1});
    EXPECT_NEAR(buildPhysicalMesh("far", far.positions, far.faces).mass.volume, 1.0, 1e-3);
    FaceMesh small = shatter::test::closedBox({0, 0, 0}, {1e-6, 1e-6, 1e-6});
    EXPECT_NEAR(buildPhysicalMesh("small", small.positions, small.faces).mass.volume, 1e-18, 1e-30);
}

TEST(PrimitivePairLimit, AFanWhosePrimitivesAllOverlapIsRefusedAboveTheLimit) {
    // 200 triangles around one centre: every prism's box overlaps every other's, so all
    // 19,900 pairs are tested for contact (nearly all touch at the centre). Under 1000
    // primitives the limit is maxOverlapsPerPrimitive × 1000.
    FaceMesh fan;
    fan.positions.emplace_back(0, 0, 0);
    const int n = 200;
    for (int i = 0; i < n; ++i) fan.positions.emplace_back(std::cos(2 * M_PI * i / n), std::sin(2 * M_PI * i / n), 0);
    for (int i = 0; i < n; ++i) fan.faces.push_back({0, 1 + i, 1 + (i + 1) % n});
    PhysicalMeshSettings s;
    s.maxOverlapsPerPrimitive = 20; // 20,000 pairs
    EXPECT_GT(buildPhysicalMesh("cap", fan.positions, fan.faces, s).connections.size(), size_t(19000));
    s.maxOverlapsPerPrimitive = 19; // 19,000 pairs
    const std::string what = errorOf([&] { buildPhysicalMesh("cap", fan.positions, fan.faces, s); });
    EXPECT_NE(what.find("body 'cap': the boxes of its 200 primitives overlap in more than 19000 pairs"), std::string::npos)
        << what;
    EXPECT_NE(what.find("more than 19 per primitive (raise it with PhysicalMeshSettings::maxOverlapsPerPrimitive, "
                        "--max-overlaps-per-primitive)"),
              std::string::npos)
        << what;
    s.maxOverlapsPerPrimitive = 0;
    EXPECT_NE(errorOf([&] { buildPhysicalMesh("cap", fan.positions, fan.faces, s); })
                  .find("maxOverlapsPerPrimitive must be >= 1"),
              std::string::npos);
}

TEST(PrimitivePairLimit, AGridHasAboutTenOverlapsPerPrimitiveAndPassesByDefault) {
    // 30,000 triangles of a flat grid (a legitimate large mesh): about 8 box overlaps each.
    FaceMesh grid = shatter::test::quadGrid(100, 150, 0.01);
    std::vector<std::vector<int>> triangles;
    for (const auto& q : grid.faces) {
        triangles.push_back({q[0], q[1], q[2]});
        triangles.push_back({q[0], q[2], q[3]});
    }
    EXPECT_EQ(buildPhysicalMesh("sheet", grid.positions, triangles).primitives.size(), 30000u);
}
