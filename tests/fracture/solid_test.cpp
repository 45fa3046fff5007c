// Cut solids: the splitter's two parts and the store that keeps cut pieces' faces.
#include <shatter/plugin/fracture/Solid.h>
#include <shatter/plugin/fracture/SolidSplitter.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
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

// What the fracture digest rests on when a primitive is clipped by several planes of a cell
// in turn (the contract any clipper that does them in one pass must keep for the same bits):
// the planes act one after another on the whole solid, so the new ids come plane by plane
// (all of the first plane's, then the second's), each cut face comes after the faces before
// it (the first cap, clipped by the second plane, before the second cap), the vertices are
// numbered by first use in face order, and a crossing is interpolated from the end with the
// lower index in the solid being split (the one the second plane cuts, not the cube).
TEST(SolidSplitter, PlanesInTurnHandOutIdsPlaneByPlaneFromTheLowerIndexEnd) {
    const Solid solid = cube();
    // Two planes cutting off the corner at (1, 1, 1); the second crosses the first's cut face.
    const Eigen::Vector3d n1 = Eigen::Vector3d(1, 1, 1).normalized(), n2 = Eigen::Vector3d(1, 3, 2).normalized();
    const double d1 = n1.dot(Eigen::Vector3d(0.8, 0.75, 0.7)), d2 = n2.dot(Eigen::Vector3d(0.7, 0.8, 0.75));
    SolidSplitter splitter;
    NewVertexIds ids(100, 1e-9);
    Solid once, twice;
    ASSERT_EQ(splitter.split(solid, -n1, -d1, 1e-9, ids, once, nullptr), SolidSplitter::Outcome::Split);
    const int afterFirst = ids.count();
    ASSERT_EQ(splitter.split(once, -n2, -d2, 1e-9, ids, twice, nullptr), SolidSplitter::Outcome::Split);
    ASSERT_GT(afterFirst, 0);
    ASSERT_GT(ids.count(), afterFirst);
    // Ids: the first plane's lie on it, the second's on the second plane.
    for (size_t v = 0; v < twice.positions.size(); ++v) {
        const int id = twice.ids[v];
        if (id < 100) continue;
        const Eigen::Vector3d& p = twice.positions[v];
        const bool first = id < 100 + afterFirst;
        EXPECT_NEAR((first ? n1 : n2).dot(p), first ? d1 : d2, 1e-12) << "id " << id;
    }
    // Faces: the cube's six (those left), then the first cap, then the second.
    ASSERT_GE(twice.faceCount(), 3);
    EXPECT_EQ(twice.kinds[size_t(twice.faceCount() - 1)], FaceKind::Crack);
    EXPECT_EQ(twice.kinds[size_t(twice.faceCount() - 2)], FaceKind::Crack);
    for (int f = 0; f + 2 < twice.faceCount(); ++f) EXPECT_EQ(twice.kinds[size_t(f)], FaceKind::Visual);
    // Vertices by first use in face order: each face's vertices are either seen before or next.
    int seen = 0;
    for (int v : twice.faceVertices) {
        ASSERT_LE(v, seen);
        if (v == seen) ++seen;
    }
    EXPECT_EQ(seen, int(twice.positions.size()));
    // The second plane's new vertices, bit for bit, from the lower-index end of an edge of `once`.
    const auto onAnEdgeFromLowerEnd = [&](const Eigen::Vector3d& p) {
        for (int f = 0; f < once.faceCount(); ++f) {
            const int begin = once.faceStart[size_t(f)], end = once.faceStart[size_t(f) + 1];
            for (int k = begin; k < end; ++k) {
                const int a = std::min(once.faceVertices[size_t(k)], once.faceVertices[size_t(k + 1 < end ? k + 1 : begin)]);
                const int b = std::max(once.faceVertices[size_t(k)], once.faceVertices[size_t(k + 1 < end ? k + 1 : begin)]);
                const double da = (-n2).dot(once.positions[size_t(a)]) + d2;
                const double db = (-n2).dot(once.positions[size_t(b)]) + d2;
                if ((da < 0) == (db < 0)) continue;
                const double t = da / (da - db);
                const Eigen::Vector3d& pa = once.positions[size_t(a)];
                const Eigen::Vector3d q = pa + t * (once.positions[size_t(b)] - pa);
                if (q == p) return true;
            }
        }
        return false;
    };
    for (size_t v = 0; v < twice.positions.size(); ++v) {
        if (twice.ids[v] < 100 + afterFirst) continue;
        EXPECT_TRUE(onAnEdgeFromLowerEnd(twice.positions[v])) << "id " << twice.ids[v];
    }
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

// Pieces fill blocks of the store one after another: thousands of them (several blocks) and
// one larger than a block each read back as added, and a piece's faces start at its own 0.
TEST(CutFaceStore, PiecesAcrossBlocksAndOneLargerThanABlockReadBack) {
    auto expectReadsBack = [](const CutFaceStore& store, int piece, const Solid& s) {
        const CutFaces faces = store[piece];
        ASSERT_EQ(faces.faceCount(), s.faceCount());
        EXPECT_EQ(std::vector<int>(faces.faceStart.begin(), faces.faceStart.end()), s.faceStart);
        EXPECT_EQ(std::vector<int>(faces.faceVertices.begin(), faces.faceVertices.end()), s.faceVertices);
        EXPECT_EQ(std::vector<FaceKind>(faces.kinds.begin(), faces.kinds.end()), s.kinds);
        EXPECT_EQ(std::vector<int>(faces.ids.begin(), faces.ids.end()), s.ids);
    };
    Solid large; // one face of 20,000 vertices: more values than a block holds
    for (int v = 0; v < 20000; ++v) {
        large.ids.push_back(7 * v);
        large.faceVertices.push_back(19999 - v);
    }
    large.addFace(FaceKind::Crack);
    std::vector<Solid> solids;
    for (int k = 0; k < 3000; ++k) {
        Solid s = cube();
        for (int& id : s.ids) id += k;
        s.kinds[size_t(k % 6)] = FaceKind(k % 3);
        solids.push_back(k == 1500 ? large : s);
    }
    CutFaceStore store;
    for (size_t k = 0; k < solids.size(); ++k) ASSERT_EQ(store.add(solids[k]), int(k));
    for (size_t k = 0; k < solids.size(); ++k) expectReadsBack(store, int(k), solids[k]);
}

// The splitter finds a crossed edge again from its other face through the edges crossed from
// the same lower vertex: cutting off the cube's corner 0, whose three edges (to 1, 2 and 4) are
// all crossed from the same lowest index, makes one new vertex per edge, and both parts close
// (the corner part a tetrahedron: the corner and the three new vertices, four faces).
TEST(SolidSplitter, EdgesCrossedFromOneVertexMakeOneNewVertexEach) {
    const Solid solid = cube();
    const Eigen::Vector3d n = Eigen::Vector3d(1, 1, 1).normalized();
    const double d = n.dot(Eigen::Vector3d(0.3, 0, 0)); // through (0.3, 0, 0), (0, 0.3, 0), (0, 0, 0.3)
    SolidSplitter splitter;
    NewVertexIds ids(100, 1e-9);
    Solid below, above;
    ASSERT_EQ(splitter.split(solid, n, d, 1e-9, ids, below, &above), SolidSplitter::Outcome::Split);
    EXPECT_EQ(ids.count(), 3);
    ASSERT_EQ(below.positions.size(), 4u);
    EXPECT_EQ(below.faceCount(), 4);
    EXPECT_EQ(below.ids[0], 10);
    EXPECT_EQ(above.positions.size(), 10u); // seven corners and the three new vertices
    EXPECT_EQ(above.faceCount(), 7);
    for (size_t v = 1; v < below.positions.size(); ++v) {
        EXPECT_GE(below.ids[v], 100);
        EXPECT_NEAR(n.dot(below.positions[v]), d, 1e-15);
        EXPECT_EQ(std::count(above.ids.begin(), above.ids.end(), below.ids[v]), 1);
    }
    const double volume = polyhedronOf(below).volume();
    EXPECT_NEAR(volume, 0.3 * 0.3 * 0.3 / 6.0, 1e-15);
    EXPECT_NEAR(volume + polyhedronOf(above).volume(), 1.0, 1e-12);
}

// A cut face must be one simple loop of the cut edges. A "solid" of two boxes (one list of
// vertices and faces) has two loops where a plane crosses both, which meet at a vertex when
// the boxes share an edge the plane crosses: neither is a cut face, and the solid stays whole
// on the side holding more of it (by summed distance: z = 0.4 leaves more above).
TEST(SolidSplitter, TwoCutLoopsKeepTheSolidWholeOnTheHeavierSide) {
    // Unit boxes with corner `at`, vertex i at at + (i & 1, i >> 1 & 1, i >> 2 & 1), numbered
    // through `index` (shared indices: shared vertices).
    const auto addBox = [](Solid& s, const Eigen::Vector3d& at, const std::array<int, 8>& index) {
        for (int i = 0; i < 8; ++i)
            if (index[size_t(i)] == int(s.positions.size())) {
                s.positions.push_back(at + Eigen::Vector3d(i & 1, i >> 1 & 1, i >> 2 & 1));
                s.ids.push_back(10 + index[size_t(i)]);
            }
        const int faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                 {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
        for (const auto& face : faces) {
            for (int k : face) s.faceVertices.push_back(index[size_t(k)]);
            s.addFace(FaceKind::Visual);
        }
    };
    const Eigen::Vector3d n(0, 0, 1);
    for (const bool touching : {false, true}) {
        Solid two;
        addBox(two, Eigen::Vector3d::Zero(), {0, 1, 2, 3, 4, 5, 6, 7});
        if (touching) // the box at (1, 1, 0) shares the first's edge (1, 1, 0)-(1, 1, 1): vertices 3 and 7
            addBox(two, Eigen::Vector3d(1, 1, 0), {3, 8, 9, 10, 7, 11, 12, 13});
        else
            addBox(two, Eigen::Vector3d(3, 0, 0), {8, 9, 10, 11, 12, 13, 14, 15});
        SolidSplitter splitter;
        NewVertexIds ids(100, 1e-9);
        Solid below, above;
        EXPECT_EQ(splitter.split(two, n, 0.4, 1e-9, ids, below, &above), SolidSplitter::Outcome::Above)
            << (touching ? "touching" : "apart");
        EXPECT_EQ(splitter.split(two, n, 0.6, 1e-9, ids, below, nullptr), SolidSplitter::Outcome::Below)
            << (touching ? "touching" : "apart");
        // One box alone splits (the same splitter, its scratch reused).
        EXPECT_EQ(splitter.split(cube(), n, 0.4, 1e-9, ids, below, &above),
                  SolidSplitter::Outcome::Split);
    }
}

// A primitive's solid: its vertices, ids and faces as they are; solidOfPrimitive marks a face
// Visual when all its ids are visual vertices, shapeOfPrimitive leaves every face Hidden.
TEST(Solid, OfAPrimitiveKeepsItsFacesAndMarksTheVisualOnes) {
    const Solid c = cube();
    std::vector<std::vector<int>> faces;
    for (int f = 0; f < c.faceCount(); ++f)
        faces.emplace_back(c.faceVertices.begin() + c.faceStart[size_t(f)], c.faceVertices.begin() + c.faceStart[size_t(f) + 1]);
    // Ids 10..17: with 14 visual vertices, only faces whose ids are all below 14 are Visual.
    const geometry::ConvexPolyhedron primitive = geometry::ConvexPolyhedron::create(c.positions, faces, c.ids);
    Solid shape, solid;
    shape.kinds.assign(9, FaceKind::Crack); // left over: replaced
    shapeOfPrimitive(primitive, shape);
    solidOfPrimitive(primitive, 14, solid);
    for (const Solid* s : {&shape, &solid}) {
        EXPECT_EQ(s->positions, c.positions);
        EXPECT_EQ(s->ids, c.ids);
        EXPECT_EQ(s->faceStart, c.faceStart);
        EXPECT_EQ(s->faceVertices, c.faceVertices);
        ASSERT_EQ(s->faceCount(), 6);
    }
    for (int f = 0; f < 6; ++f) {
        EXPECT_EQ(shape.kinds[size_t(f)], FaceKind::Hidden);
        bool visual = true;
        for (int k = c.faceStart[size_t(f)]; k < c.faceStart[size_t(f) + 1]; ++k) visual &= c.ids[size_t(c.faceVertices[size_t(k)])] < 14;
        EXPECT_EQ(solid.kinds[size_t(f)], visual ? FaceKind::Visual : FaceKind::Hidden) << "face " << f;
    }
    EXPECT_EQ(solid.kinds[0], FaceKind::Visual); // vertices 0, 2, 3, 1: ids 10..13
}
