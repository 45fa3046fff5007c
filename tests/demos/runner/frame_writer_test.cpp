// A frame file must read back as the meshes that were written: same counts, 1-based
// in-range indices, one object per mesh, and the same bytes for the same input.
#include "demos/runner/FrameWriter.h"

#include "test_files.h"

#include <gtest/gtest.h>

using namespace shatter;
using namespace shatter::demo;
using shatter::demo::test::readObj;
using shatter::demo::test::readText;
using shatter::demo::test::TempDir;

namespace {

NamedMesh pyramid(const std::string& name, Eigen::Vector3d offset) {
    NamedMesh m;
    m.name = name;
    m.mesh.positions = {offset + Eigen::Vector3d(0, 0, 0), offset + Eigen::Vector3d(1, 0, 0),
                        offset + Eigen::Vector3d(1, 0, 1), offset + Eigen::Vector3d(0, 0, 1),
                        offset + Eigen::Vector3d(0.5, 1, 0.5)};
    m.mesh.faces = {{0, 1, 2, 3}, {0, 4, 1}, {1, 4, 2}, {2, 4, 3}, {3, 4, 0}};
    return m;
}

} // namespace

TEST(FrameWriter, FileNamesHaveAtLeastFourDigitsAndWidenForLongRuns) {
    EXPECT_EQ(frameFileName(1, 240, "obj"), "frame_0001.obj");
    EXPECT_EQ(frameFileName(240, 240, "png"), "frame_0240.png");
    EXPECT_EQ(frameFileName(9999, 9999, "obj"), "frame_9999.obj");
    EXPECT_EQ(frameFileName(7, 12000, "obj"), "frame_00007.obj");
    EXPECT_EQ(frameFileName(12000, 12000, "obj"), "frame_12000.obj");
}

TEST(FrameWriter, WrittenFileReadsBackWithEveryVertexFaceAndObject) {
    TempDir dir;
    FrameWriter writer(dir.path(), 240);
    const std::vector<NamedMesh> meshes = {pyramid("left", {-2, 0, 0}), pyramid("right", {2, 0, 0}),
                                           pyramid("up", {0, 3, 0})};
    const auto path = writer.write(3, meshes, "test frame");
    EXPECT_EQ(path, dir.path() / "frame_0003.obj");
    EXPECT_EQ(writer.written(), 1);

    const auto obj = readObj(path);
    EXPECT_EQ(obj.vertices, 15);
    EXPECT_EQ(obj.faces, 15);
    EXPECT_EQ(obj.objects, (std::vector<std::string>{"left", "right", "up"}));
    EXPECT_EQ(obj.verticesPerObject, (std::vector<int>{5, 5, 5}));
    EXPECT_EQ(obj.facesPerObject, (std::vector<int>{5, 5, 5}));
    EXPECT_EQ(obj.badIndices, 0);
    EXPECT_EQ(obj.shortFaces, 0);
    EXPECT_EQ(obj.badNumbers, 0);
}

TEST(FrameWriter, FacesOfLaterObjectsAreOffsetByEarlierVertices) {
    std::string text;
    appendObj(text, {pyramid("a", {0, 0, 0}), pyramid("b", {0, 0, 0})}, "x");
    // The quad of the second pyramid refers to its own first four vertices, 6..9.
    EXPECT_NE(text.find("o b\nv "), std::string::npos);
    EXPECT_NE(text.find("\nf 6 7 8 9\n"), std::string::npos) << text;
    EXPECT_NE(text.find("\nf 1 2 3 4\n"), std::string::npos) << text;
}

TEST(FrameWriter, CrackFacesGetTheirMaterialAndPlanarTextureCoordinates) {
    // The base quads (y = 0) are crack faces: under `usemtl crack`, one `vt` per corner (the
    // quad projected on its plane, in metres: x and -z here), numbered on over the file.
    auto cracked = [](const std::string& name) {
        NamedMesh m = pyramid(name, {0, 0, 0});
        m.mesh.crackFace = {true, false, false, false, false};
        return m;
    };
    std::string text;
    appendObj(text, {cracked("a"), cracked("b")}, "x");
    EXPECT_NE(text.find("usemtl crack\nvt 0.000000 0.000000\nvt 1.000000 0.000000\nvt 1.000000 -1.000000\n"
                        "vt 0.000000 -1.000000\nf 1/1 2/2 3/3 4/4\nusemtl surface\nf 1 5 2\n"),
              std::string::npos)
        << text;
    EXPECT_NE(text.find("\nf 6/5 7/6 8/7 9/8\n"), std::string::npos) << text;
}

TEST(FrameWriter, CoordinatesUseFixedSixDecimalsWithoutNegativeZero) {
    NamedMesh m;
    m.name = "p";
    m.mesh.positions = {{1.0 / 3.0, -1e-9, -2.5}};
    std::string text;
    appendObj(text, {m}, "c");
    EXPECT_NE(text.find("v 0.333333 0.000000 -2.500000\n"), std::string::npos) << text;
}

TEST(FrameWriter, SameMeshesGiveTheSameBytes) {
    TempDir dir;
    FrameWriter writer(dir.path(), 10);
    const std::vector<NamedMesh> meshes = {pyramid("a", {0.1, 0.2, 0.3})};
    const auto first = readText(writer.write(1, meshes, "same"));
    const auto second = readText(writer.write(2, meshes, "same"));
    EXPECT_EQ(first, second);
    EXPECT_FALSE(first.empty());
}

TEST(FrameWriter, NamesStayOnOneLine) {
    NamedMesh m = pyramid("two\nlines", {0, 0, 0});
    std::string text;
    appendObj(text, {m}, "c");
    EXPECT_NE(text.find("o two_lines\n"), std::string::npos);
}

TEST(FrameWriter, UnwritableDirectoryIsAnErrorNamingTheFile) {
    FrameWriter writer("/nonexistent-shatter-dir/sub", 5);
    try {
        writer.write(1, {pyramid("a", {0, 0, 0})}, "c");
        FAIL() << "expected an error";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("frame_0001.obj"), std::string::npos) << e.what();
    }
}
