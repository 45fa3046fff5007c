// Physical mesh creation (source 000 §3.1): open faces become prisms of face area ×
// thickness, closed convex parts become one primitive each.
#include <shatter/plugin/geometry/Extrusion.h>
#include <shatter/plugin/common/InputError.h>
#include <shatter/plugin/geometry/PhysicalMesh.h>
#include <shatter/plugin/geometry/Polygon.h>

#include "MeshFixtures.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

using namespace shatter::geometry;
using shatter::InputError;
using shatter::test::FaceMesh;

namespace {

// Volumes and areas are compared within 1e-12 relative: exact formulas in double.
constexpr double kRel = 1e-12;

// Every vertex on or behind every face plane (round-off only: 1e-12 of the size), and
// the centroid strictly behind every plane, so the normals point outward.
void expectConvexWithOutwardNormals(const ConvexPolyhedron& p) {
    const double size = p.bounds().diagonal();
    const Eigen::Vector3d centroid = p.massProperties(1.0).centerOfMass;
    for (const auto& plane : p.planes()) {
        for (const auto& v : p.vertices()) EXPECT_LE(plane.signedDistance(v), 1e-12 * size);
        EXPECT_LT(plane.signedDistance(centroid), 0.0);
    }
}

double area(const std::vector<Eigen::Vector3d>& points, const std::vector<int>& polygon) {
    return 0.5 * polygonAreaVector(points, polygon).norm();
}

// Top of an extruded prism: its vertices that carry visual ids (< visualCount), in order.
std::vector<int> topIds(const ConvexPolyhedron& p, int visualCount) {
    std::vector<int> ids;
    for (int id : p.globalIds())
        if (id < visualCount) ids.push_back(id);
    return ids;
}

PhysicalMeshSettings withThickness(double t) {
    PhysicalMeshSettings s;
    s.thickness = t;
    return s;
}

std::string buildError(const FaceMesh& m, const PhysicalMeshSettings& s, const std::string& name = "door") {
    try {
        buildPhysicalMesh(name, m.positions, m.faces, s);
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

// Closed L-shaped block: an L hexagon (area 3) extruded 1 along z; non-convex.
FaceMesh closedLBlock() {
    const std::vector<Eigen::Vector2d> l = {{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}};
    FaceMesh m;
    for (double z : {0.0, 1.0})
        for (const auto& p : l) m.positions.emplace_back(p.x(), p.y(), z);
    m.faces.push_back({5, 4, 3, 2, 1, 0});   // bottom, seen from below
    m.faces.push_back({6, 7, 8, 9, 10, 11}); // top
    for (int i = 0; i < 6; ++i) m.faces.push_back({i, (i + 1) % 6, 6 + (i + 1) % 6, 6 + i});
    return m;
}

} // namespace

TEST(Extrusion, TiltedQuadBecomesOnePrismOfAreaTimesThickness) {
    FaceMesh m;
    m.positions = {{0, 0, 0}, {0.3, 0, 0}, {0.3, 0.2, 0}, {0, 0.2, 0}};
    m.faces = {{0, 1, 2, 3}};
    const Eigen::Isometry3d pose = Eigen::Translation3d(1, -2, 0.5) * Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized());
    shatter::test::transform(m, pose);
    const double t = 0.01;
    const PhysicalMesh mesh = buildPhysicalMesh("panel", m.positions, m.faces, withThickness(t));
    ASSERT_EQ(mesh.primitives.size(), 1u);
    EXPECT_EQ(mesh.sourceFace, std::vector<int>{0});
    const ConvexPolyhedron& prism = mesh.primitives[0];
    EXPECT_NEAR(prism.volume(), 0.3 * 0.2 * t, kRel * 0.3 * 0.2 * t);
    expectConvexWithOutwardNormals(prism);
    // Top vertices are the face vertices (ids 0..3); bottom ones moved by -t·n (ids 4..7).
    const Eigen::Vector3d n = pose.linear() * Eigen::Vector3d::UnitZ();
    ASSERT_EQ(prism.vertices().size(), 8u);
    for (size_t k = 0; k < 8; ++k) {
        const int id = prism.globalIds()[k];
        const Eigen::Vector3d expected = id < 4 ? m.positions[id] : Eigen::Vector3d(m.positions[id - 4] - t * n);
        EXPECT_LT((prism.vertices()[k] - expected).norm(), 1e-15) << "vertex " << k;
    }
    // The plane through the top vertices faces along the face normal.
    int topPlanes = 0;
    for (const auto& plane : prism.planes())
        if ((plane.normal - n).norm() < 1e-12) ++topPlanes;
    EXPECT_EQ(topPlanes, 1);
    EXPECT_EQ(mesh.globalIdCount, 8);
    EXPECT_EQ(mesh.thickness, t);
}

TEST(Extrusion, RegularHeptagonIsOnePrism) {
    FaceMesh m;
    const double r = 0.4;
    std::vector<int> face;
    for (int i = 0; i < 7; ++i) {
        const double a = 2.0 * std::numbers::pi * i / 7.0;
        m.positions.emplace_back(r * std::cos(a), r * std::sin(a), 0.2);
        face.push_back(i);
    }
    m.faces = {face};
    const double t = 0.02;
    const PhysicalMesh mesh = buildPhysicalMesh("h", m.positions, m.faces, withThickness(t));
    ASSERT_EQ(mesh.primitives.size(), 1u);
    const double expectedArea = 3.5 * r * r * std::sin(2.0 * std::numbers::pi / 7.0);
    EXPECT_NEAR(mesh.primitives[0].volume(), expectedArea * t, kRel * expectedArea * t);
    EXPECT_EQ(mesh.primitives[0].faces().size(), 9u); // top, bottom, 7 sides
    expectConvexWithOutwardNormals(mesh.primitives[0]);
}

TEST(Extrusion, CollinearVerticesStayInOnePrism) {
    // Square of side 1 with a vertex in the middle of every edge.
    FaceMesh m;
    m.positions = {{0, 0, 0}, {0.5, 0, 0}, {1, 0, 0}, {1, 0.5, 0}, {1, 1, 0}, {0.5, 1, 0}, {0, 1, 0}, {0, 0.5, 0}};
    m.faces = {{0, 1, 2, 3, 4, 5, 6, 7}};
    const PhysicalMesh mesh = buildPhysicalMesh("s", m.positions, m.faces, withThickness(0.1));
    ASSERT_EQ(mesh.primitives.size(), 1u);
    EXPECT_NEAR(mesh.primitives[0].volume(), 0.1, kRel * 0.1);
    expectConvexWithOutwardNormals(mesh.primitives[0]);
}

TEST(Extrusion, NonPlanarQuadSplitsIntoTwoTrianglePrisms) {
    FaceMesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0.2}, {0, 1, 0}};
    m.faces = {{0, 1, 2, 3}};
    const double t = 0.05;
    const PhysicalMesh mesh = buildPhysicalMesh("q", m.positions, m.faces, withThickness(t));
    ASSERT_EQ(mesh.primitives.size(), 2u);
    EXPECT_EQ(mesh.sourceFace, (std::vector<int>{0, 0}));
    std::vector<int> used;
    double volume = 0.0, topArea = 0.0;
    for (const auto& prism : mesh.primitives) {
        expectConvexWithOutwardNormals(prism);
        const std::vector<int> top = topIds(prism, 4);
        ASSERT_EQ(top.size(), 3u);
        // Each triangle is a right prism along its own normal: volume = area × t.
        EXPECT_NEAR(prism.volume(), area(m.positions, top) * t, kRel * prism.volume());
        volume += prism.volume();
        topArea += area(m.positions, top);
        used.insert(used.end(), top.begin(), top.end());
    }
    std::sort(used.begin(), used.end());
    // The two triangles share one diagonal: two corners are used twice, all four at least once.
    EXPECT_EQ(std::unique(used.begin(), used.end()) - used.begin(), 4);
    const double split02 = area(m.positions, {0, 1, 2}) + area(m.positions, {0, 2, 3});
    const double split13 = area(m.positions, {0, 1, 3}) + area(m.positions, {1, 2, 3});
    EXPECT_TRUE(std::abs(topArea - split02) < kRel || std::abs(topArea - split13) < kRel) << topArea;
    EXPECT_NEAR(volume, topArea * t, kRel * volume);
}

TEST(Extrusion, ConcaveLHexagonIsSplitAndKeepsItsVolume) {
    FaceMesh m;
    m.positions = {{0, 0, 0}, {2, 0, 0}, {2, 1, 0}, {1, 1, 0}, {1, 2, 0}, {0, 2, 0}};
    m.faces = {{0, 1, 2, 3, 4, 5}};
    const double t = 0.1;
    const PhysicalMesh mesh = buildPhysicalMesh("l", m.positions, m.faces, withThickness(t));
    ASSERT_EQ(mesh.primitives.size(), 4u); // a hexagon has 4 triangles
    double volume = 0.0;
    std::vector<int> used;
    for (const auto& prism : mesh.primitives) {
        expectConvexWithOutwardNormals(prism);
        volume += prism.volume();
        const auto top = topIds(prism, 6);
        used.insert(used.end(), top.begin(), top.end());
        // No triangle crosses the notch: its centroid lies inside the L.
        const Eigen::Vector3d c = prism.massProperties(1.0).centerOfMass;
        EXPECT_FALSE(c.x() > 1.0 && c.y() > 1.0) << c.transpose();
    }
    EXPECT_NEAR(volume, 3.0 * t, kRel * 3.0 * t);
    std::sort(used.begin(), used.end());
    EXPECT_EQ(std::unique(used.begin(), used.end()) - used.begin(), 6); // every vertex carried
}

TEST(Extrusion, ClosedCubeIsOnePrimitiveWithoutExtrusion) {
    const FaceMesh m = shatter::test::closedBox({1, 2, 3}, {1.3, 2.2, 3.1});
    const PhysicalMesh mesh = buildPhysicalMesh("box", m.positions, m.faces, withThickness(0.5));
    ASSERT_EQ(mesh.primitives.size(), 1u);
    EXPECT_EQ(mesh.sourceFace, std::vector<int>{-1});
    EXPECT_EQ(mesh.globalIdCount, 8); // nothing extruded: no inner vertices
    const ConvexPolyhedron& p = mesh.primitives[0];
    EXPECT_NEAR(p.volume(), 0.3 * 0.2 * 0.1, kRel * 0.006);
    expectConvexWithOutwardNormals(p);
    for (size_t k = 0; k < p.vertices().size(); ++k) EXPECT_EQ(p.vertices()[k], m.positions[p.globalIds()[k]]);
    std::vector<int> ids = p.globalIds();
    std::sort(ids.begin(), ids.end());
    EXPECT_EQ(ids, (std::vector<int>{0, 1, 2, 3, 4, 5, 6, 7}));
    EXPECT_TRUE(mesh.warnings.empty());
}

TEST(Extrusion, ClosedTetrahedronIsOnePrimitive) {
    FaceMesh m;
    const double a = 0.3;
    m.positions = {{0, 0, 0}, {a, 0, 0}, {0, a, 0}, {0, 0, a}};
    m.faces = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
    const PhysicalMesh mesh = buildPhysicalMesh("tet", m.positions, m.faces);
    ASSERT_EQ(mesh.primitives.size(), 1u);
    EXPECT_NEAR(mesh.primitives[0].volume(), a * a * a / 6.0, kRel * a * a * a);
    EXPECT_EQ(mesh.globalIdCount, 4);
}

TEST(Extrusion, ClosedPartWithDuplicatedVerticesIsStillOnePrimitive) {
    // Every face has its own copies of its corners (as some exporters write them).
    const FaceMesh box = shatter::test::closedBox({0, 0, 0}, {1, 1, 1});
    FaceMesh m;
    for (const auto& face : box.faces) {
        std::vector<int> copy;
        for (int v : face) {
            copy.push_back(int(m.positions.size()));
            m.positions.push_back(box.positions[v]);
        }
        m.faces.push_back(copy);
    }
    const PhysicalMesh mesh = buildPhysicalMesh("split", m.positions, m.faces);
    ASSERT_EQ(mesh.primitives.size(), 1u);
    EXPECT_NEAR(mesh.primitives[0].volume(), 1.0, kRel);
    std::vector<int> ids = mesh.primitives[0].globalIds();
    std::sort(ids.begin(), ids.end());
    ASSERT_EQ(ids.size(), 24u); // every copy carries its id so that the welder moves it
    for (int i = 0; i < 24; ++i) EXPECT_EQ(ids[i], i);
}

TEST(Extrusion, InwardWoundClosedPartIsFlippedWithAWarning) {
    FaceMesh m = shatter::test::closedBox({0, 0, 0}, {1, 2, 3});
    for (auto& f : m.faces) std::reverse(f.begin(), f.end());
    const PhysicalMesh mesh = buildPhysicalMesh("inside_out", m.positions, m.faces);
    ASSERT_EQ(mesh.primitives.size(), 1u);
    EXPECT_NEAR(mesh.primitives[0].volume(), 6.0, kRel * 6.0);
    ASSERT_EQ(mesh.warnings.size(), 1u);
    EXPECT_EQ(mesh.warnings[0].rfind("body 'inside_out': the closed part (face 0, face 1", 0), 0u)
        << mesh.warnings[0];
    // The visual faces are flipped too, so they face outward for the renderer.
    const FaceMesh original = shatter::test::closedBox({0, 0, 0}, {1, 2, 3});
    EXPECT_EQ(mesh.visual.faces, original.faces);
}

TEST(Extrusion, OpenCubeIsExtrudedFaceByFace) {
    FaceMesh m = shatter::test::closedBox({0, 0, 0}, {1, 1, 1});
    m.faces.pop_back(); // no +x side
    const double t = 0.05;
    const PhysicalMesh mesh = buildPhysicalMesh("open", m.positions, m.faces, withThickness(t));
    ASSERT_EQ(mesh.primitives.size(), 5u);
    EXPECT_EQ(mesh.sourceFace, (std::vector<int>{0, 1, 2, 3, 4}));
    EXPECT_EQ(mesh.globalIdCount, 16);
    for (const auto& p : mesh.primitives) {
        EXPECT_NEAR(p.volume(), t, kRel * t);
        expectConvexWithOutwardNormals(p);
        // Extruded inward: the prism lies inside the unit cube.
        EXPECT_TRUE((p.bounds().min.array() >= -1e-15).all() && (p.bounds().max.array() <= 1 + 1e-15).all());
    }
}

TEST(Extrusion, ClosedButConcavePartIsExtruded) {
    const FaceMesh m = closedLBlock();
    const double t = 0.01;
    const PhysicalMesh mesh = buildPhysicalMesh("l", m.positions, m.faces, withThickness(t));
    // Top and bottom L hexagons: 4 triangles each; 6 rectangular sides: 1 prism each.
    EXPECT_EQ(mesh.primitives.size(), 14u);
    double volume = 0.0;
    for (const auto& p : mesh.primitives) volume += p.volume();
    const double surface = 2 * 3.0 + 8.0 * 1.0; // two L faces + perimeter 8 × height 1
    EXPECT_NEAR(volume, surface * t, kRel * surface * t);
}

TEST(Extrusion, DefaultThicknessIsOnePercentOfTheDiagonal) {
    const FaceMesh m = shatter::test::quadGrid(3, 4, 1.0); // 3 × 4 × 0: diagonal 5
    const PhysicalMesh mesh = buildPhysicalMesh("grid", m.positions, m.faces);
    EXPECT_DOUBLE_EQ(mesh.thickness, 0.05);
    EXPECT_DOUBLE_EQ(mesh.contactTolerance, 5e-4);
    EXPECT_EQ(mesh.density, 1000.0);
}

TEST(Extrusion, ExtrudeFaceDirectlyGivesTheSamePrism) {
    const std::vector<Eigen::Vector3d> points = {{0, 0, 0}, {2, 0, 0}, {2, 1, 0}, {0, 1, 0}};
    const auto prisms = extrudeFace(points, {0, 1, 2, 3}, 0.25, 1e-9, 4, "test");
    ASSERT_EQ(prisms.size(), 1u);
    EXPECT_NEAR(prisms[0].volume(), 0.5, kRel);
    EXPECT_NEAR(prisms[0].bounds().min.z(), -0.25, 1e-15);
}

TEST(PhysicalMeshInput, BadSettingsNameTheBodyAndTheValue) {
    const FaceMesh m = shatter::test::quadGrid(1, 1, 1.0);
    PhysicalMeshSettings s;
    s.thickness = -1;
    EXPECT_EQ(buildError(m, s), "body 'door': thickness must be positive and finite (or 0 for the default), got -1");
    s = {};
    s.thickness = INFINITY;
    EXPECT_NE(buildError(m, s).find("thickness must be positive and finite (or 0 for the default), got inf"), std::string::npos);
    s = {};
    s.density = 0.0;
    EXPECT_EQ(buildError(m, s), "body 'door': density must be positive and finite, got 0");
    s.density = NAN;
    EXPECT_EQ(buildError(m, s), "body 'door': density must be positive and finite, got nan");
    s = {};
    s.contactTolerance = -1e-3;
    EXPECT_EQ(buildError(m, s),
              "body 'door': contact tolerance must be positive and finite (or 0 for the default), got -0.001");
}

TEST(PhysicalMeshInput, BadFacesAreErrorsOrSkippedWithAWarning) {
    FaceMesh m = shatter::test::quadGrid(2, 1, 1.0);
    m.faces.push_back({0, 1, 9});
    EXPECT_EQ(buildError(m, {}), "body 'door': face 2: vertex index 9 is out of range (6 vertices)");
    m = shatter::test::quadGrid(2, 1, 1.0);
    m.positions[4].y() = NAN;
    EXPECT_EQ(buildError(m, {}), "body 'door': face 0: vertex 4 has a non-finite coordinate");
    m = shatter::test::quadGrid(2, 1, 1.0);
    m.faces.push_back({0, 1, 2});       // collinear
    m.faces.push_back({0, 0, 1});       // two distinct vertices
    m.faces.push_back({0, 1, 1, 4, 3}); // kept as 0 1 4 3
    const PhysicalMesh mesh = buildPhysicalMesh("door", m.positions, m.faces);
    ASSERT_EQ(mesh.warnings.size(), 1u);
    EXPECT_EQ(mesh.warnings[0], "body 'door': skipped 2 degenerate faces (face 2, face 3)");
    ASSERT_EQ(mesh.visual.faces.size(), 3u);
    EXPECT_EQ(mesh.visual.faces[2], (std::vector<int>{0, 1, 4, 3}));
    EXPECT_EQ(mesh.sourceFace, (std::vector<int>{0, 1, 2}));
    FaceMesh flat;
    flat.positions = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
    flat.faces = {{0, 1, 2}};
    EXPECT_EQ(buildError(flat, {}), "body 'door': no faces (all 1 faces are degenerate)");
    flat.faces.clear();
    EXPECT_EQ(buildError(flat, {}), "body 'door': no faces");
}
