// Tear lines in the OBJ file: `tear.<body>` objects of `l` polylines over the body's vertices,
// and a message naming file, line and body for each kind of bad one.
#include <shatter/plugin/common/InputError.h>
#include <shatter/plugin/geometry/ObjFile.h>
#include <shatter/plugin/geometry/PhysicalMesh.h>
#include <shatter/plugin/geometry/TearLines.h>

#include <gtest/gtest.h>

#include <cmath>

using namespace shatter::geometry;
using shatter::InputError;

namespace {

// Two quads side by side (x in [0, 2]) sharing the edge x = 1 (vertices 2 and 5, 1-based).
const std::string kTwoQuads = "o cloth\nv 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nv 1 1 0\nv 2 1 0\n"
                              "f 1 2 5 4\nf 2 3 6 5\n";

PhysicalObject build(const std::string& text) {
    PhysicalMeshSettings settings;
    settings.thickness = 0.01;
    return buildPhysicalObject(parseObj(text, "cloth.obj"), settings);
}

std::string buildError(const std::string& text) {
    try {
        build(text);
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

} // namespace

TEST(TearLines, PolylineOverMeshVerticesBecomesTheBodysTearEdges) {
    const PhysicalObject object = build(kTwoQuads + "o tear.cloth\nl 2 5\n");
    ASSERT_EQ(object.bodies.size(), 1u);
    const PhysicalMesh& cloth = object.bodies[0];
    ASSERT_EQ(cloth.tearEdges.size(), 1u);
    const auto [a, b] = cloth.tearEdges[0];
    EXPECT_EQ(cloth.visual.positions[size_t(a)], Eigen::Vector3d(1, 0, 0));
    EXPECT_EQ(cloth.visual.positions[size_t(b)], Eigen::Vector3d(1, 1, 0));
}

TEST(TearLines, PointsMatchByPositionWithinTheTolerance) {
    // The tear line has vertices of its own, 1e-7 m off the mesh's (the tolerance is 1e-6 of
    // the 2 × 1 m sheet's diagonal).
    const PhysicalObject object =
        build(kTwoQuads + "o tear.cloth\nv 1.0000001 0 0\nv 1 0.9999999 0\nl 7 8\n");
    EXPECT_EQ(object.bodies[0].tearEdges.size(), 1u);
    EXPECT_NEAR(tearPointTolerance(object.bodies[0]), 1e-6 * std::sqrt(5.0), 1e-15);
}

TEST(TearLines, PolylinesOutsideTearObjectsAreIgnored) {
    const PhysicalObject object = build(kTwoQuads + "l 1 2 3\no guide\nl 4 5\n");
    ASSERT_EQ(object.bodies.size(), 1u);
    EXPECT_TRUE(object.bodies[0].tearEdges.empty());
}

TEST(TearLines, BadTearLinesNameFileLineAndBody) {
    EXPECT_EQ(buildError(kTwoQuads + "o tear.curtain\nl 2 5\n"),
              "cloth.obj:10: tear object 'tear.curtain': body 'curtain' does not exist (bodies: cloth)");
    EXPECT_EQ(buildError(kTwoQuads + "o tear.\nl 2 5\n"), "cloth.obj:10: tear object 'tear.': names no body (write tear.<body>)");
    const std::string off = buildError(kTwoQuads + "o tear.cloth\nv 1.5 0.5 0\nl 2 7\n");
    EXPECT_NE(off.find("cloth.obj:12: tear line of body 'cloth': point 2 (1.5 0.5 0) is not a vertex"), std::string::npos)
        << off;
    EXPECT_EQ(buildError(kTwoQuads + "o tear.cloth\nl 1 6\n"),
              "cloth.obj:11: tear line of body 'cloth': points 1 and 2 are not joined by an edge of the body's faces");
    EXPECT_EQ(buildError(kTwoQuads + "o tear.cloth\nf 1 2 5\n"),
              "cloth.obj:11: tear object 'tear.cloth' holds a face; a tear object holds only polylines (l)");
    EXPECT_EQ(buildError(kTwoQuads + "o tear.cloth\nl 2\n"), "cloth.obj:11: line needs at least 2 vertices, got 1");
    EXPECT_EQ(buildError(kTwoQuads + "o tear.cloth\nl 2 5x\n"),
              "cloth.obj:11: malformed vertex index '5x' in line element '5x'");
    EXPECT_EQ(buildError(kTwoQuads + "o tear.cloth\nl 2 5/1/1\n"),
              "cloth.obj:11: malformed line element '5/1/1' (only v or v/vt)");
    EXPECT_EQ(buildError(kTwoQuads + "o tear.cloth\nl 2 9\n"),
              "cloth.obj:11: vertex index 9 is out of range: 6 defined before this line");
}
