// The OBJ reader: what it keeps of good files, and a message naming file and line for
// every kind of broken one.
#include <shatter/plugin/common/InputError.h>
#include <shatter/plugin/geometry/ObjFile.h>

#include "MeshFixtures.h"

#include <gtest/gtest.h>

#include <filesystem>

using namespace shatter::geometry;
using shatter::InputError;

namespace {

// The message of the InputError that parsing `text` throws ("" if none).
std::string parseError(const std::string& text, const std::string& name = "bad.obj") {
    try {
        parseObj(text, name);
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

std::vector<int> indices(std::initializer_list<int> v) { return v; }

} // namespace

TEST(ObjReader, ReadsTrianglesQuadsAndAHeptagon) {
    const std::string text = "# three faces\n"
                             "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                             "v 2 0 0\nv 3 0 0\nv 3.5 0.8 0\nv 3 1.6 0\nv 2.5 1.8 0\nv 2 1.6 0\nv 1.8 0.8 0\n"
                             "f 1 2 3\n"
                             "f 1 2 3 4\n"
                             "f 5 6 7 8 9 10 11\n";
    const ObjFile file = parseObj(text, "dir/shapes.obj");
    EXPECT_EQ(file.path, "dir/shapes.obj");
    ASSERT_EQ(file.positions.size(), 11u);
    EXPECT_EQ(file.positions[6], Eigen::Vector3d(3.5, 0.8, 0.0));
    EXPECT_EQ(file.positionLines[0], 2);
    EXPECT_EQ(file.positionLines[10], 12);
    ASSERT_EQ(file.objects.size(), 1u);
    EXPECT_EQ(file.objects[0].name, "shapes"); // faces before any `o` belong to the file stem
    EXPECT_EQ(file.objects[0].line, 0);
    const auto& faces = file.objects[0].faces;
    ASSERT_EQ(faces.size(), 3u);
    EXPECT_EQ(faces[0].vertices, indices({0, 1, 2}));
    EXPECT_EQ(faces[0].line, 13);
    EXPECT_EQ(faces[1].vertices, indices({0, 1, 2, 3}));
    EXPECT_EQ(faces[2].vertices, indices({4, 5, 6, 7, 8, 9, 10}));
    EXPECT_EQ(faces[2].line, 15);
    EXPECT_TRUE(file.warnings.empty());
}

TEST(ObjReader, ReadsEveryVertexReferenceForm) {
    const std::string text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n"
                             "vt 0 0\nvt 1 0\nvt 0 1\n"
                             "vn 0 0 1\n"
                             "f 1/1 2/2 3/3\n"
                             "f 2/2/1 4/3/1 3/1/1\n"
                             "f 1//1 2//1 4//1\n"
                             "f 1 2/1 3//1\n";
    const ObjFile file = parseObj(text, "forms.obj");
    const auto& faces = file.objects.at(0).faces;
    ASSERT_EQ(faces.size(), 4u);
    EXPECT_EQ(faces[0].vertices, indices({0, 1, 2}));
    EXPECT_EQ(faces[1].vertices, indices({1, 3, 2}));
    EXPECT_EQ(faces[2].vertices, indices({0, 1, 3}));
    EXPECT_EQ(faces[3].vertices, indices({0, 1, 2}));
}

TEST(ObjReader, NegativeIndicesCountBackFromTheLastVertexSoFar) {
    const std::string text = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                             "f -4 -3 -2 -1\n"
                             "v 5 0 0\nv 6 0 0\nv 5 1 0\n"
                             "f -3 -2 -1\n"
                             "vt 0 0\nvn 0 0 1\n"
                             "f -1/-1/-1 -2 -3\n";
    const ObjFile file = parseObj(text, "rel.obj");
    const auto& faces = file.objects.at(0).faces;
    ASSERT_EQ(faces.size(), 3u) << (file.warnings.empty() ? "" : file.warnings[0]);
    EXPECT_EQ(faces[0].vertices, indices({0, 1, 2, 3}));
    EXPECT_EQ(faces[1].vertices, indices({4, 5, 6}));
    EXPECT_EQ(faces[2].vertices, indices({6, 5, 4}));
}

TEST(ObjReader, ObjectAndGroupStatementsStartNamedObjects) {
    const std::string text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n"
                             "f 1 2 3\n"          // line 5: implicit object "parts"
                             "o door\n"           // line 6
                             "f 1 3 4\n"
                             "g door.handle\n"    // line 8
                             "f 1 4 2\n"
                             "o empty\n"          // no faces: dropped
                             "g two words\n"      // line 11
                             "f 2 4 3\n";
    const ObjFile file = parseObj(text, "parts.obj");
    ASSERT_EQ(file.objects.size(), 4u);
    EXPECT_EQ(file.objects[0].name, "parts");
    EXPECT_EQ(file.objects[1].name, "door");
    EXPECT_EQ(file.objects[1].line, 6);
    EXPECT_EQ(file.objects[2].name, "door.handle");
    EXPECT_EQ(file.objects[2].line, 8);
    EXPECT_EQ(file.objects[3].name, "two words");
    EXPECT_EQ(file.objects[3].line, 11);
    EXPECT_EQ(file.objects[3].faces.at(0).line, 12);
}

TEST(ObjReader, HandlesCrLfCommentsBlankLinesTabsAndContinuations) {
    const std::string text = "\xEF\xBB\xBF# exported on Windows\r\n"
                             "\r\n"
                             "v\t0 0 0   # origin\r\n"
                             "v 1 0 0\r\n"
                             "v 1 1 0\r\n"
                             "v +0 1 -0\r\n"
                             "f 1 2 \\\r\n"   // line 7, continued on line 8
                             "  3 4\r\n"
                             "   \r\n"
                             "f 1 3 4";      // line 10, no final newline
    const ObjFile file = parseObj(text, "crlf.obj");
    ASSERT_EQ(file.positions.size(), 4u);
    EXPECT_EQ(file.positions[3], Eigen::Vector3d(0, 1, 0));
    const auto& faces = file.objects.at(0).faces;
    ASSERT_EQ(faces.size(), 2u);
    EXPECT_EQ(faces[0].vertices, indices({0, 1, 2, 3}));
    EXPECT_EQ(faces[0].line, 7);
    EXPECT_EQ(faces[1].line, 10);
    EXPECT_TRUE(file.warnings.empty());
}

TEST(ObjReader, IgnoresOtherStatementsAndWarnsAboutUnknownOnes) {
    const std::string text = "mtllib a.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\nvp 0.5\n"
                             "usemtl red\ns off\nl 1 2\np 1\n"
                             "frobnicate 1 2 3\n" // line 12
                             "f 1 2 3\n";
    const ObjFile file = parseObj(text, "other.obj");
    EXPECT_EQ(file.objects.at(0).faces.size(), 1u);
    ASSERT_EQ(file.warnings.size(), 1u);
    EXPECT_EQ(file.warnings[0], "other.obj: ignored 1 unknown statement (line 12)");
}

TEST(ObjReader, NumbersAreStrictButAcceptEveryDecimalForm) {
    const ObjFile file = parseObj("v 1e-3 -2.5E+2 .5\nv 1e-400 0 0\nv 1. 0 1\nf 1 2 3\n", "num.obj");
    EXPECT_EQ(file.positions[0], Eigen::Vector3d(1e-3, -250.0, 0.5));
    EXPECT_EQ(file.positions[1].x(), 0.0); // underflow is zero to double precision, not an error
    EXPECT_EQ(file.positions[2], Eigen::Vector3d(1.0, 0.0, 1.0));
}

TEST(ObjReader, LoadsAFileAndNamesItsPath) {
    const std::string path = shatter::test::writeTempFile("tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    const ObjFile file = loadObj(path);
    EXPECT_EQ(file.path, path);
    EXPECT_EQ(file.objects.at(0).name, "tri");
    const std::string bad = shatter::test::writeTempFile("bad_line.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n");
    try {
        loadObj(bad);
        FAIL() << "no error";
    } catch (const InputError& e) {
        EXPECT_EQ(std::string(e.what()).rfind(bad + ":4: ", 0), 0u) << e.what();
    }
}

TEST(ObjReader, MissingFileOrDirectoryCannotBeOpened) {
    const std::string missing = (std::filesystem::temp_directory_path() / "shatter_no_such_file.obj").string();
    try {
        loadObj(missing);
        FAIL() << "no error";
    } catch (const InputError& e) {
        EXPECT_EQ(std::string(e.what()), missing + ": cannot open: No such file or directory");
    }
    const std::string dir = std::filesystem::temp_directory_path().string();
    try {
        loadObj(dir);
        FAIL() << "no error";
    } catch (const InputError& e) {
        EXPECT_EQ(std::string(e.what()), dir + ": cannot open: Is a directory");
    }
}

struct BrokenCase {
    const char* what;
    std::string text;
    int line;
    std::string detail; // must appear in the message after "bad.obj:<line>: "
};

class ObjReaderBroken : public ::testing::TestWithParam<BrokenCase> {};

TEST_P(ObjReaderBroken, NamesFileLineAndProblem) {
    const BrokenCase& c = GetParam();
    const std::string message = parseError(c.text);
    const std::string prefix = "bad.obj:" + std::to_string(c.line) + ": ";
    EXPECT_EQ(message.rfind(prefix, 0), 0u) << c.what << ": " << message;
    EXPECT_NE(message.find(c.detail), std::string::npos) << c.what << ": " << message;
}

const std::string kTriangle = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";

INSTANTIATE_TEST_SUITE_P(
    EveryProblem, ObjReaderBroken,
    ::testing::Values(
        BrokenCase{"malformed number", kTriangle + "v 1 2 x\nf 1 2 3\n", 4, "malformed number 'x'"},
        BrokenCase{"binary bytes are escaped", kTriangle + "v 1 2 \x1b[2J\xff\n", 4, "malformed number '\\x1B[2J\\xFF'"},
        BrokenCase{"long tokens are cut", kTriangle + "v 1 2 " + std::string(5000, '7') + "x\n", 4,
                   "malformed number '" + std::string(40, '7') + "...' (5001 bytes)"},
        BrokenCase{"exponent past the long long range", "v 11e9223372036854775807 0 0\n", 1,
                   "non-finite coordinate '11e9223372036854775807'"},
        BrokenCase{"exponent at the long long range", "v 1e9223372036854775807 0 0\n", 1,
                   "non-finite coordinate '1e9223372036854775807'"},
        BrokenCase{"face cut short", kTriangle + "f 1 2 3\nf 3 ", 5, "face needs at least 3 vertices, got 1 (is the file cut short?)"},
        BrokenCase{"face of two vertices", kTriangle + "f 1 2\n", 4, "face needs at least 3 vertices, got 2"},
        BrokenCase{"face without vertices", kTriangle + "f\n", 4, "face needs at least 3 vertices, got 0"},
        BrokenCase{"number with junk", "v 1 2 3\nv 1.5.2 0 0\n", 2, "malformed number '1.5.2'"},
        BrokenCase{"decimal comma", "v 1,5 0 0\n", 1, "malformed number '1,5'"},
        BrokenCase{"missing coordinate", kTriangle + "\nv 1 2\n", 5, "vertex needs 3 coordinates (x y z), got 2"},
        BrokenCase{"nan", "v 0 0 0\nv 1 nan 0\n", 2, "non-finite coordinate 'nan'"},
        BrokenCase{"inf", "v 0 0 0\nv 1 0 -inf\n", 2, "non-finite coordinate '-inf'"},
        BrokenCase{"overflow", "v 1e999 0 0\n", 1, "non-finite coordinate '1e999'"},
        BrokenCase{"index 0", kTriangle + "f 0 1 2\n", 4, "vertex index 0 is invalid (OBJ indices start at 1)"},
        BrokenCase{"index out of range", kTriangle + "# c\nf 1 2 9\n", 5,
                   "vertex index 9 is out of range: 3 defined before this line"},
        BrokenCase{"negative index out of range", kTriangle + "f -1 -2 -4\n", 4,
                   "vertex index -4 is out of range: 3 defined before this line"},
        BrokenCase{"vertex used before it is defined", "v 0 0 0\nv 1 0 0\nf 1 2 3\nv 0 1 0\n", 3,
                   "vertex index 3 is out of range: 2 defined before this line"},
        BrokenCase{"huge index", kTriangle + "f 1 2 99999999999\n", 4, "vertex index '99999999999' is out of range"},
        BrokenCase{"malformed index", kTriangle + "f 1 2 3x\n", 4, "malformed vertex index '3x' in face element '3x'"},
        BrokenCase{"malformed texture index", kTriangle + "vt 0 0\nf 1/a 2 3\n", 5,
                   "malformed texture coordinate index 'a' in face element '1/a'"},
        BrokenCase{"texture index out of range", kTriangle + "vt 0 0\nf 1/1 2/2 3/1\n", 5,
                   "texture coordinate index 2 is out of range: 1 defined before this line"},
        BrokenCase{"normal index out of range", kTriangle + "f 1//1 2//1 3//1\n", 4,
                   "normal index 1 is out of range: 0 defined before this line"},
        BrokenCase{"too many slashes", kTriangle + "f 1/1/1/1 2 3\n", 4, "malformed face element '1/1/1/1'"},
        BrokenCase{"error after a continuation", kTriangle + "f 1 2 \\\n 7\n", 4, "vertex index 7 is out of range"}),
    [](const ::testing::TestParamInfo<BrokenCase>& info) {
        std::string name = info.param.what;
        for (char& c : name)
            if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
        return name;
    });

TEST(ObjReader, ObjectNamesKeepOnlyPrintableAsciiAsIs) {
    // Names reach messages ("body 'NAME'"), so a terminal never sees the file's raw bytes.
    const ObjFile file = parseObj("o \x1b[31mred\xff door\n" + kTriangle + "f 1 2 3\n", "names.obj");
    EXPECT_EQ(file.objects.at(0).name, "\\x1B[31mred\\xFF door");
}

TEST(ObjReader, AFileWithoutFacesIsAnError) {
    EXPECT_EQ(parseError("v 0 0 0\nv 1 0 0\n", "empty.obj"), "empty.obj: no faces");
    EXPECT_EQ(parseError("", "nothing.obj"), "nothing.obj: no faces");
    // Only degenerate faces: skipped, then nothing is left.
    EXPECT_EQ(parseError(kTriangle + "f 1 2 1\n", "flat.obj"), "flat.obj: no faces");
}

TEST(ObjReader, DegenerateFacesAreSkippedAndCountedInOneWarning) {
    const std::string text = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\n" // lines 1-5
                             "f 1 2 3 4\n"   // 6 kept
                             "f 2 1 2\n"     // 7 two distinct vertices, one repeated
                             "f 1 1 2\n"     // 8 two distinct vertices
                             "f 1 2 5\n"     // 9 collinear: zero area
                             "f 1 2 2 3\n"   // 10 kept as 1 2 3 (repeat removed)
                             "f 3 3 3\n"     // 11
                             "f 1 2 3 1 4\n" // 12 vertex 1 repeated: self-touching
                             "f 2 1 1\n"     // 13
                             "f 4 4 4 4\n";  // 14
    const ObjFile file = parseObj(text, "deg.obj");
    const auto& faces = file.objects.at(0).faces;
    ASSERT_EQ(faces.size(), 2u);
    EXPECT_EQ(faces[0].line, 6);
    EXPECT_EQ(faces[1].line, 10);
    EXPECT_EQ(faces[1].vertices, indices({0, 1, 2}));
    ASSERT_EQ(file.warnings.size(), 1u);
    EXPECT_EQ(file.warnings[0], "deg.obj: skipped 7 degenerate faces (lines 7, 8, 9, 11, 12, ...)");
}

TEST(ObjReader, ZeroAreaIsRelativeToTheFileSize) {
    // Threshold: Newell normal (twice the area) ≤ 1e-12 × diagonal² = 2e-12 here. A 10 µm
    // triangle (normal 1.7e-10) is a real face; a 1 m sliver 1e-13 high (normal 1e-13) is not.
    const std::string text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1e-5\nv 1e-5 0 0\nv 0 1e-5 0\nv 1 1e-13 0\n"
                             "f 1 2 3\nf 4 5 6\nf 1 2 7\n";
    const ObjFile file = parseObj(text, "small.obj");
    EXPECT_EQ(file.objects.at(0).faces.size(), 2u);
    ASSERT_EQ(file.warnings.size(), 1u);
    EXPECT_EQ(file.warnings[0], "small.obj: skipped 1 degenerate face (line 10)");
}
