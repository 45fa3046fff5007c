// Tet input: the TetGen reader on good and malformed files, arrays, and the generators.
#include <shatter/plugin/common/InputError.h>
#include <shatter/plugin/lattice/TetFaces.h>
#include <shatter/plugin/lattice/TetGenProgram.h>
#include <shatter/plugin/lattice/TetGenReader.h>
#include <shatter/plugin/lattice/TetGenerators.h>

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

namespace shatter::lattice {
namespace {

namespace fs = std::filesystem;

class TetGenFiles : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() /
               ("shatter_tetgen_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }
    std::string write(const std::string& node, const std::string& ele) {
        const std::string stem = (dir_ / "mesh").string();
        std::ofstream(stem + ".node") << node;
        std::ofstream(stem + ".ele") << ele;
        return stem;
    }
    // The error message of reading `stem`, or "" when it reads.
    static std::string error(const std::string& path) {
        try {
            readTetGen(path);
        } catch (const InputError& e) {
            return e.what();
        }
        return "";
    }
    fs::path dir_;
};

// Two tets sharing the face (1, 2, 3), one-based like TetGen's default output.
const char* kNodes = "# two tets\n5 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n5 1 1 1\n";
const char* kEle = "2 4 0\n1 1 2 3 4\n2 2 5 3 4   # second\n";

TEST_F(TetGenFiles, ReadsOneBasedFilesWithComments) {
    const TetMesh mesh = readTetGen(write(kNodes, kEle) + ".ele");
    ASSERT_EQ(mesh.nodes.size(), 5u);
    ASSERT_EQ(mesh.tets.size(), 2u);
    EXPECT_EQ(mesh.tets[0], (Tet{0, 1, 2, 3}));
    EXPECT_NEAR(signedVolume(mesh, mesh.tets[0]), 1.0 / 6.0, 1e-15);
    EXPECT_GT(signedVolume(mesh, mesh.tets[1]), 0.0);
    EXPECT_TRUE(mesh.warnings.empty());
    EXPECT_EQ(buildTetFaces(mesh).shared.size(), 1u);
}

TEST_F(TetGenFiles, ReadsZeroBasedSecondOrderElementsWithAttributes) {
    const std::string stem = write("5 3 1 1\n0 0 0 0 7 1\n1 1 0 0 7 1\n2 0 1 0 7 1\n3 0 0 1 7 1\n4 1 1 1 7 1\n",
                                   "2 10 1\n0 0 1 2 3 9 9 9 9 9 9 5\n1 1 4 2 3 9 9 9 9 9 9 5\n");
    const TetMesh mesh = readTetGen(stem);
    EXPECT_EQ(mesh.tets[1], (Tet{1, 4, 2, 3}));
}

TEST_F(TetGenFiles, AllInvertedFileIsReorderedWithAWarning) {
    const TetMesh mesh = readTetGen(write(kNodes, "2 4 0\n1 1 3 2 4\n2 2 3 5 4\n"));
    ASSERT_EQ(mesh.warnings.size(), 1u);
    EXPECT_NE(mesh.warnings[0].find("opposite corner order"), std::string::npos);
    for (const Tet& t : mesh.tets) EXPECT_GT(signedVolume(mesh, t), 0.0);
}

TEST_F(TetGenFiles, MalformedFilesNameFileLineAndElement) {
    const std::string stem = (dir_ / "mesh").string();
    struct Case {
        std::string node, ele, expect;
    };
    const std::vector<Case> cases = {
        {kNodes, "2 4 0\n1 1 2 3 4\n2 2 5 3 9\n", "mesh.ele:3: tetrahedron 2: node 9 does not exist"},
        {kNodes, "2 4 0\n1 1 2 3 4\n2 2 3 5 4\n", "mesh.ele:3: tetrahedron 2 is inverted"},
        {kNodes, "2 4 0\n1 1 2 3 4\n2 2 3 2 4\n", "mesh.ele:3: tetrahedron 2 uses node 2 twice"},
        {"5 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n5 0.5 0.5 0\n", "2 4 0\n1 1 2 3 4\n2 1 2 5 3\n",
         "mesh.ele:3: tetrahedron 2 is degenerate"},
        {kNodes, "2 4 0\n1 1 2 3 4\n", "mesh.ele:2: ends before tetrahedron 2 of 2"},
        {kNodes, "2 3 0\n", "mesh.ele:1: nodes per tetrahedron must be 4 or 10"},
        {kNodes, "two 4 0\n", "mesh.ele:1: tetrahedron count 'two' is not an integer"},
        {kNodes, "0 4 0\n", "mesh.ele:1: tetrahedron count must be positive, got 0"},
        {"5 3 0 0\n1 0 0 0\n2 1 0 nan\n", kEle, "mesh.node:3: point 2 coordinate 'nan' is not finite"},
        {"5 3 0 0\n1 0 0 0\n3 1 0 0\n", kEle, "mesh.node:3: point numbered 3, expected 2"},
        {"5 2 0 0\n", kEle, "mesh.node:1: dimension must be 3"},
        {"5 3 0 0\n1 0 0 0\n2 1 0\n", kEle, "mesh.node:3: a point line needs"},
        {"", kEle, "mesh.node:0: ends before the header"},
        {"8 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n5 5 0 0\n6 6 0 0\n7 5 1 0\n8 5 0 1\n",
         "2 4 0\n1 1 2 3 4\n2 5 6 7 8\n", "is disconnected: 2 pieces; tetrahedron 2 shares no chain of faces with tetrahedron 1"},
    };
    for (const Case& c : cases) {
        write(c.node, c.ele);
        const std::string message = error(stem);
        EXPECT_NE(message.find(c.expect), std::string::npos) << "expected '" << c.expect << "' in '" << message << "'";
    }
    EXPECT_NE(error((dir_ / "missing").string()).find("missing.node: cannot open the file"), std::string::npos);
}

// Under ASan, an allocation of the declared size would abort these (allocation-size-too-big).
TEST_F(TetGenFiles, DeclaredCountsAllocateOnlyWhatTheFileCanHold) {
    const std::string stem = (dir_ / "mesh").string();
    struct Case {
        std::string node, ele, expect;
    };
    const std::vector<Case> cases = {
        {"1000000000 3 0 0\n1 0 0 0\n", kEle, "mesh.node:2: ends before point 2 of 1000000000"},
        {"1000000000000 3 0 0\n1 0 0 0\n", kEle, "mesh.node:1: point count 1000000000000 is above the supported 2147483647"},
        {"9223372036854775807 3 0 0\n", kEle, "mesh.node:1: point count 9223372036854775807 is above the supported"},
        {"99999999999999999999 3 0 0\n", kEle, "mesh.node:1: point count '99999999999999999999' is not an integer"},
        {kNodes, "2147483647 4 0\n1 1 2 3 4\n", "mesh.ele:2: ends before tetrahedron 2 of 2147483647"},
        {kNodes, "1000000000 10 0\n", "mesh.ele:1: ends before tetrahedron 1 of 1000000000"},
    };
    for (const Case& c : cases) {
        write(c.node, c.ele);
        const std::string message = error(stem);
        EXPECT_NE(message.find(c.expect), std::string::npos) << "expected '" << c.expect << "' in '" << message << "'";
    }
}

TEST_F(TetGenFiles, RepeatedTetsInAnyOrderAreErrorsNamingBoth) {
    const std::string stem = (dir_ / "mesh").string();
    // The same four nodes as tetrahedron 1: as written, an even permutation (same
    // orientation) and an odd one (which alone would read as inverted).
    for (const char* repeat : {"1 2 3 4", "2 1 4 3", "2 1 3 4"}) {
        write(kNodes, std::string("3 4 0\n1 1 2 3 4\n2 2 5 3 4\n3 ") + repeat + "\n");
        EXPECT_NE(error(stem).find("mesh.ele:4: tetrahedron 3 has the same four nodes as tetrahedron 1"), std::string::npos)
            << repeat << ": " << error(stem);
    }
}

TEST_F(TetGenFiles, VolumesThatOverflowAreErrorsNotInversions) {
    const std::string stem = (dir_ / "mesh").string();
    // Edges of 1e200 m: the volume's products overflow to infinity and their difference to NaN.
    write("5 3 0 0\n1 0 0 0\n2 1e200 0 0\n3 0 1e200 0\n4 0 0 1e200\n5 1e200 1e200 1e200\n", kEle);
    EXPECT_NE(error(stem).find("mesh.ele:2: tetrahedron 1 has a volume that is not a finite number"), std::string::npos)
        << error(stem);
}

TEST_F(TetGenFiles, BinaryBytesInMessagesAreEscaped) {
    const std::string stem = (dir_ / "mesh").string();
    write("5 3 0 0\n1 0 0 \x1b[31m\x80\n", kEle);
    EXPECT_NE(error(stem).find("mesh.node:2: point 1 coordinate '\\x1B[31m\\x80' is not a number"), std::string::npos)
        << error(stem);
}

TEST_F(TetGenFiles, WriteThenReadIsExact) {
    GeneratorOptions o;
    o.jitter = 0.15;
    const TetMesh box = tetBox({1.0, 0.5, 0.3}, {3, 2, 2}, o);
    writeTetGen(box, (dir_ / "box").string());
    const TetMesh back = readTetGen((dir_ / "box.ele").string());
    EXPECT_EQ(back.tets, box.tets);
    EXPECT_EQ(back.nodes, box.nodes); // 17 significant digits round-trip doubles exactly
}

TEST(TetArrays, BadArraysAreErrorsNamingTheMesh) {
    const std::vector<Eigen::Vector3d> nodes = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    EXPECT_NO_THROW(makeTetMesh("ok", nodes, {{0, 1, 2, 3}}));
    auto message = [&](std::vector<Eigen::Vector3d> n, std::vector<Tet> t) -> std::string {
        try {
            makeTetMesh("arrays", std::move(n), std::move(t));
        } catch (const InputError& e) {
            return e.what();
        }
        return "";
    };
    EXPECT_NE(message(nodes, {{0, 2, 1, 3}}).find("arrays: tetrahedron 0 is inverted"), std::string::npos);
    EXPECT_NE(message(nodes, {{0, 1, 2, 4}}).find("node 4, which does not exist"), std::string::npos);
    EXPECT_NE(message(nodes, {}).find("arrays: has no tetrahedra"), std::string::npos);
    EXPECT_NE(message(nodes, {{0, 1, 2, 3}, {3, 2, 1, 0}}).find("arrays: tetrahedron 1 has the same four nodes as tetrahedron 0"),
              std::string::npos);
    auto bad = nodes;
    bad[1].x() = INFINITY;
    EXPECT_NE(message(bad, {{0, 1, 2, 3}}).find("node 1 has a non-finite coordinate"), std::string::npos);
    // Three tets on one face: not a manifold solid.
    auto three = nodes;
    three.push_back({1, 1, 1});
    three.push_back({0.2, 0.2, 1.5});
    EXPECT_NE(message(three, {{0, 1, 2, 3}, {1, 4, 2, 3}, {1, 2, 3, 5}}).find("shared by more than two"),
              std::string::npos);
}

double totalVolume(const TetMesh& mesh) {
    double v = 0.0;
    for (const Tet& t : mesh.tets) v += signedVolume(mesh, t);
    return v;
}

TEST(TetGenerators, BoxTilesItsVolumeWithSixTetsPerCell) {
    const TetMesh box = tetBox({2.0, 1.0, 0.4}, {10, 5, 2});
    EXPECT_EQ(box.tets.size(), 600u);
    EXPECT_NEAR(totalVolume(box), 0.8, 1e-12);
    // Conforming: every inner face is shared by exactly two tets, the surface is the box's
    // 2·(10·5 + 10·2 + 5·2) squares of 2 triangles.
    const TetFaces faces = buildTetFaces(box);
    EXPECT_EQ(faces.boundaryCount, 4 * (50 + 20 + 10));
    EXPECT_EQ(int(faces.shared.size()), (4 * 600 - faces.boundaryCount) / 2);
}

TEST(TetGenerators, JitterKeepsTheShapeAndIsSeeded) {
    GeneratorOptions o;
    o.jitter = 0.2;
    o.seed = 7;
    const TetMesh a = tetBox({1.0, 1.0, 1.0}, {6, 6, 6}, o);
    const TetMesh b = tetBox({1.0, 1.0, 1.0}, {6, 6, 6}, o);
    o.seed = 8;
    const TetMesh c = tetBox({1.0, 1.0, 1.0}, {6, 6, 6}, o);
    EXPECT_EQ(a.nodes, b.nodes);
    EXPECT_NE(a.nodes, c.nodes);
    EXPECT_NEAR(totalVolume(a), 1.0, 1e-12); // surface nodes slide within the faces
    for (const Tet& t : a.tets) EXPECT_GT(signedVolume(a, t), 0.0);
    const TetMesh plain = tetBox({1.0, 1.0, 1.0}, {6, 6, 6});
    double moved = 0.0;
    for (size_t i = 0; i < a.nodes.size(); ++i) moved = std::max(moved, (a.nodes[i] - plain.nodes[i]).norm());
    EXPECT_GT(moved, 0.01);
    EXPECT_LE(moved, 0.2 * std::sqrt(3.0) / 6.0 + 1e-12);
}

TEST(TetGenerators, SlabAndCylinder) {
    const TetMesh slab = tetSlab(1.2, 0.6, 0.02, 0.05, 1);
    EXPECT_EQ(slab.tets.size(), size_t(24 * 12 * 6));
    EXPECT_NEAR(totalVolume(slab), 1.2 * 0.6 * 0.02, 1e-14);
    const int rings = 4, layers = 3, sides = 6 * rings;
    const TetMesh cyl = tetCylinder(0.3, 0.9, rings, layers);
    // The disc is 6·r² triangles per layer, each prism 3 tets; the outline a regular polygon.
    EXPECT_EQ(cyl.tets.size(), size_t(6 * rings * rings * 3 * layers));
    const double polygon = 0.5 * sides * 0.09 * std::sin(2 * M_PI / sides);
    EXPECT_NEAR(totalVolume(cyl), polygon * 0.9, 1e-12);
    GeneratorOptions o;
    o.jitter = 0.2;
    EXPECT_NO_THROW(tetCylinder(0.3, 0.9, rings, layers, o));
}

TEST(TetGenerators, BadParametersAreErrors) {
    GeneratorOptions o;
    o.jitter = 0.5;
    EXPECT_THROW(tetBox({1, 1, 1}, {2, 2, 2}, o), InputError);
    EXPECT_THROW(tetBox({1, -1, 1}, {2, 2, 2}), InputError);
    EXPECT_THROW(tetBox({1, 1, NAN}, {2, 2, 2}), InputError);
    EXPECT_THROW(tetBox({1, 1, 1}, {0, 2, 2}), InputError);
    EXPECT_THROW(tetCylinder(0.0, 1.0, 2, 2), InputError);
    EXPECT_THROW(tetSlab(1.0, 1.0, 0.1, 0.0), InputError);
}

} // namespace
} // namespace shatter::lattice

namespace shatter::lattice {
namespace {

// Only where the external program is installed (it is not a dependency).
TEST(TetGenProgram, TetrahedralizesAClosedSurfaceWhenInstalled) {
    if (!tetgenAvailable()) GTEST_SKIP() << "tetgen is not installed";
    const std::vector<Eigen::Vector3d> cube = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                                               {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
    const std::vector<std::vector<int>> faces = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4},
                                                 {2, 3, 7, 6}, {1, 2, 6, 5}, {0, 4, 7, 3}};
    TetGenProgramOptions o;
    o.maxVolume = 0.01;
    const TetMesh mesh = tetrahedralize("cube", cube, faces, o);
    double volume = 0;
    for (const Tet& t : mesh.tets) volume += signedVolume(mesh, t);
    EXPECT_NEAR(volume, 1.0, 1e-9);
    EXPECT_GT(mesh.tets.size(), 100u);
    // TetGen orders corners as the reader expects (positive volume): nothing was reordered.
    EXPECT_TRUE(mesh.warnings.empty()) << mesh.warnings.front();
}

TEST(TetGenProgram, AMissingProgramIsAnError) {
    TetGenProgramOptions o;
    o.program = "no-such-tetgen-program";
    EXPECT_THROW(tetrahedralize("cube", {{0, 0, 0}}, {}, o), InputError);
}

} // namespace
} // namespace shatter::lattice
