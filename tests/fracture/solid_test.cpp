// Cut solids: the splitter's two parts and the store that keeps cut pieces' faces.
#include <shatter/plugin/fracture/Solid.h>
#include <shatter/plugin/fracture/SolidSplitter.h>

#include <gtest/gtest.h>

#include <vector>

using namespace shatter;
using namespace shatter::fracture;

namespace {

// A unit cube's solid (ids 10..17, faces of four vertices, all Visual).
Solid cube() {
    Solid s;
    for (int i = 0; i < 8; ++i) {
        s.positions.emplace_back(i & 1, i >> 1 & 1, i >> 2 & 1);
        s.ids.push_back(10 + i);
    }
    const int faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (const auto& face : faces) {
        s.faceVertices.insert(s.faceVertices.end(), face, face + 4);
        s.addFace(FaceKind::Visual);
    }
    return s;
}

void expectSameSolid(const Solid& a, const Solid& b) {
    EXPECT_EQ(a.positions, b.positions);
    EXPECT_EQ(a.ids, b.ids);
    EXPECT_EQ(a.faceStart, b.faceStart);
    EXPECT_EQ(a.faceVertices, b.faceVertices);
    EXPECT_EQ(a.kinds, b.kinds);
}

} // namespace

// The part below is the same whether the part above is written in the same pass or not, and
// the two parts' volumes add up to the cube's (a tilted plane through four edges and a corner
// region, so that faces lose vertices on both sides).
TEST(SolidSplitter, BelowIsTheSameWithOrWithoutAboveAndTheVolumesAddUp) {
    const Solid solid = cube();
    const Eigen::Vector3d n = Eigen::Vector3d(1, 2, 3).normalized();
    const double d = n.dot(Eigen::Vector3d(0.4, 0.5, 0.45));
    SolidSplitter splitter;
    NewVertexIds ids1(100, 1e-9), ids2(100, 1e-9);
    Solid belowOnly, below, above;
    ASSERT_EQ(splitter.split(solid, n, d, 1e-9, ids1, belowOnly, nullptr), SolidSplitter::Outcome::Split);
    ASSERT_EQ(splitter.split(solid, n, d, 1e-9, ids2, below, &above), SolidSplitter::Outcome::Split);
    expectSameSolid(belowOnly, below);
    EXPECT_EQ(below.kinds.back(), FaceKind::Crack);
    EXPECT_EQ(above.kinds.back(), FaceKind::Crack);
    const double volume = polyhedronOf(below).volume() + polyhedronOf(above).volume();
    EXPECT_NEAR(volume, 1.0, 1e-12);
    for (const Eigen::Vector3d& p : below.positions) EXPECT_LE(n.dot(p) - d, 1e-9);
    for (const Eigen::Vector3d& p : above.positions) EXPECT_GE(n.dot(p) - d, -1e-9);
}

// Each piece added to the store reads back with its own faces (indices into its own ids),
// kinds and ids, whatever was added before it.
TEST(CutFaceStore, EachPieceReadsBackItsFacesKindsAndIds) {
    const Solid first = cube();
    Solid second = cube();
    SolidSplitter splitter;
    NewVertexIds ids(100, 1e-9);
    Solid below;
    ASSERT_EQ(splitter.split(second, Eigen::Vector3d(0, 0, 1), 0.5, 1e-9, ids, below, nullptr),
              SolidSplitter::Outcome::Split);
    CutFaceStore store;
    EXPECT_EQ(store.add(first), 0);
    EXPECT_EQ(store.add(below), 1);
    const std::vector<const Solid*> solids{&first, &below};
    for (int piece = 0; piece < 2; ++piece) {
        const Solid& s = *solids[size_t(piece)];
        const CutFaces faces = store[piece];
        ASSERT_EQ(faces.faceCount(), s.faceCount());
        EXPECT_EQ(std::vector<int>(faces.ids.begin(), faces.ids.end()), s.ids);
        EXPECT_EQ(std::vector<FaceKind>(faces.kinds.begin(), faces.kinds.end()), s.kinds);
        for (int f = 0; f < s.faceCount(); ++f) {
            const std::vector<int> read(faces.faceVertices.begin() + faces.faceStart[size_t(f)],
                                        faces.faceVertices.begin() + faces.faceStart[size_t(f) + 1]);
            const std::vector<int> kept(s.faceVertices.begin() + s.faceStart[size_t(f)],
                                        s.faceVertices.begin() + s.faceStart[size_t(f) + 1]);
            EXPECT_EQ(read, kept);
        }
    }
}
