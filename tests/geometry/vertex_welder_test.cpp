// Visual-mesh welding (source 000 §3.4): each visual vertex is the average of the primitive
// vertices that carry its id.
#include <shatter/plugin/geometry/PhysicalMesh.h>
#include <shatter/plugin/geometry/VisualMesh.h>

#include "MeshFixtures.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <stdexcept>

using namespace shatter::geometry;
using shatter::test::FaceMesh;

namespace {

PhysicalMesh extrudedGrid(int nx = 4, int ny = 3) {
    const FaceMesh grid = shatter::test::quadGrid(nx, ny, 0.25);
    PhysicalMeshSettings s;
    s.thickness = 0.02;
    return buildPhysicalMesh("grid", grid.positions, grid.faces, s);
}

// Every primitive moved by its own random rigid motion of size ~1e-3 (rotation angle and
// translation), about its centroid.
std::vector<ConvexPolyhedron> jiggled(const std::vector<ConvexPolyhedron>& primitives, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    std::vector<ConvexPolyhedron> out;
    for (const auto& p : primitives) {
        const Eigen::Vector3d c = p.bounds().center();
        const Eigen::Vector3d axis = Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized();
        const Eigen::Isometry3d motion = Eigen::Translation3d(1e-3 * Eigen::Vector3d(u(rng), u(rng), u(rng))) *
                                         Eigen::Translation3d(c) * Eigen::AngleAxisd(1e-3 * u(rng), axis) *
                                         Eigen::Translation3d(-c);
        out.push_back(p.transformed(motion));
    }
    return out;
}

// Without the primitives at `removed` (ascending), the others in order.
std::vector<ConvexPolyhedron> without(const std::vector<ConvexPolyhedron>& primitives, const std::vector<int>& removed) {
    std::vector<ConvexPolyhedron> out;
    for (size_t p = 0; p < primitives.size(); ++p)
        if (!std::binary_search(removed.begin(), removed.end(), int(p))) out.push_back(primitives[p]);
    return out;
}

// `count` distinct ascending indices below `size`.
std::vector<int> someOf(int size, int count, std::mt19937& rng) {
    std::vector<int> all(size_t(size), 0);
    for (int i = 0; i < size; ++i) all[size_t(i)] = i;
    std::shuffle(all.begin(), all.end(), rng);
    all.resize(size_t(count));
    std::sort(all.begin(), all.end());
    return all;
}

// The welder's list of uncarried ids is exactly the visual ids carries() denies (any order).
void expectUncarriedListed(const VertexWelder& welder, int n) {
    std::vector<int> listed = welder.uncarried(), expected;
    std::sort(listed.begin(), listed.end());
    for (int id = 0; id < n; ++id)
        if (!welder.carries(id)) expected.push_back(id);
    EXPECT_EQ(listed, expected);
}

// Everything a welder shows: weld() of `moved` (bit for bit, and which ids it writes: the
// others keep a mark), weld() of the same vertices flat, and the carriers of every id.
void expectSameWelder(const VertexWelder& edited, const VertexWelder& fresh, const std::vector<ConvexPolyhedron>& moved,
                      int n) {
    const Eigen::Isometry3d t = Eigen::Translation3d(0.3, -1.0, 2.0) * Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitY());
    std::vector<Eigen::Vector3d> a(size_t(n), Eigen::Vector3d(7, 7, 7)), b = a;
    edited.weld(moved, t, a);
    fresh.weld(moved, t, b);
    ASSERT_EQ(a.size(), b.size());
    for (size_t id = 0; id < a.size(); ++id) ASSERT_EQ(a[id], b[id]) << "id " << id; // bitwise
    std::vector<Eigen::Vector3d> flat;
    for (const auto& p : moved) flat.insert(flat.end(), p.vertices().begin(), p.vertices().end());
    edited.weld(flat, t, a);
    fresh.weld(flat, t, b);
    EXPECT_EQ(a, b);
    for (int id = 0; id < n + 4; ++id) EXPECT_EQ(edited.primitivesCarrying({id}), fresh.primitivesCarrying({id})) << id;
    expectUncarriedListed(edited, n);
}

} // namespace

TEST(VertexWelder, AtRestGivesTheInputPositionsExactly) {
    const PhysicalMesh mesh = extrudedGrid();
    const VertexWelder welder(mesh.primitives, int(mesh.visual.positions.size()));
    std::vector<Eigen::Vector3d> positions;
    welder.weld(mesh.primitives, Eigen::Isometry3d::Identity(), positions);
    ASSERT_EQ(positions.size(), mesh.visual.positions.size());
    for (size_t i = 0; i < positions.size(); ++i) EXPECT_EQ(positions[i], mesh.visual.positions[i]) << i; // bitwise

    // In another frame: the transformed input, to round-off of one transform (1e-15 × size).
    const Eigen::Isometry3d t = Eigen::Translation3d(0.3, -0.1, 2) * Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitY());
    welder.weld(mesh.primitives, t, positions);
    for (size_t i = 0; i < positions.size(); ++i)
        EXPECT_LT((positions[i] - t * mesh.visual.positions[i]).norm(), 1e-15 * 4.0) << i;
}

TEST(VertexWelder, MovedPrimitivesWeldToTheAverageOfTheirVertices) {
    const PhysicalMesh mesh = extrudedGrid();
    const int n = int(mesh.visual.positions.size());
    const VertexWelder welder(mesh.primitives, n);
    const std::vector<ConvexPolyhedron> moved = jiggled(mesh.primitives, 5);
    const Eigen::Isometry3d t = Eigen::Translation3d(1, 2, 3) * Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitX());
    std::vector<Eigen::Vector3d> positions;
    welder.weld(moved, t, positions);

    // Reference by brute force.
    std::vector<Eigen::Vector3d> sum(n, Eigen::Vector3d::Zero());
    std::vector<int> count(n, 0);
    for (const auto& p : moved)
        for (size_t k = 0; k < p.vertices().size(); ++k)
            if (p.globalIds()[k] < n) {
                sum[p.globalIds()[k]] += p.vertices()[k];
                ++count[p.globalIds()[k]];
            }
    for (int id = 0; id < n; ++id) {
        ASSERT_GT(count[id], 0);
        EXPECT_LT((positions[id] - t * (sum[id] / count[id])).norm(), 1e-14) << id;
    }

    // By hand: interior grid vertex (1, 1) = index 6 is a corner of the quads (0,0), (1,0),
    // (0,1), (1,1), i.e. primitives 0, 1, 4, 5, where it is top vertex 2, 3, 1, 0.
    const Eigen::Vector3d byHand =
        (moved[0].vertices()[2] + moved[1].vertices()[3] + moved[4].vertices()[1] + moved[5].vertices()[0]) / 4.0;
    ASSERT_EQ(moved[0].globalIds()[2], 6);
    ASSERT_EQ(moved[5].globalIds()[0], 6);
    EXPECT_EQ(count[6], 4);
    EXPECT_LT((positions[6] - t * byHand).norm(), 1e-14);
    // The jiggle really moved it: welded differs from rest by about 1e-3, not by round-off.
    EXPECT_GT((positions[6] - t * mesh.visual.positions[6]).norm(), 1e-5);
}

TEST(VertexWelder, FlatVerticesWeldLikePolyhedra) {
    const PhysicalMesh mesh = extrudedGrid();
    const int n = int(mesh.visual.positions.size());
    const VertexWelder welder(mesh.primitives, n);
    const std::vector<ConvexPolyhedron> moved = jiggled(mesh.primitives, 8);
    std::vector<Eigen::Vector3d> flat;
    for (const auto& p : moved) flat.insert(flat.end(), p.vertices().begin(), p.vertices().end());
    const Eigen::Isometry3d t = Eigen::Translation3d(0.3, -1.0, 2.0) * Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitY());
    std::vector<Eigen::Vector3d> a, b;
    welder.weld(moved, t, a);
    welder.weld(flat, t, b);
    EXPECT_EQ(a, b);
}

TEST(VertexWelder, IdsNoPrimitiveCarriesAreLeftAlone) {
    // Two positions that no face uses: no primitive carries their ids.
    shatter::test::FaceMesh grid = shatter::test::quadGrid(2, 2, 1.0);
    const int n = int(grid.positions.size());
    grid.positions.emplace_back(5, 5, 5);
    grid.positions.emplace_back(6, 6, 6);
    const PhysicalMesh mesh = buildPhysicalMesh("grid", grid.positions, grid.faces);
    const VertexWelder welder(mesh.primitives, n + 2);
    std::vector<Eigen::Vector3d> positions(n + 2, Eigen::Vector3d(7, 7, 7));
    welder.weld(mesh.primitives, Eigen::Isometry3d::Identity(), positions);
    EXPECT_EQ(positions[n], Eigen::Vector3d(7, 7, 7));
    EXPECT_EQ(positions[n + 1], Eigen::Vector3d(7, 7, 7));
    for (int i = 0; i < n; ++i) EXPECT_EQ(positions[i], grid.positions[i]);
}

TEST(VertexWelder, EveryIdListsThePrimitivesThatCarryIt) {
    // The constructor's per-id lists, inner ids (>= the visual count: the extrusion's far
    // side) included, against a search of every primitive's ids: primitivesCarrying follows
    // them, and fillHoles and removePrimitives edit them.
    const PhysicalMesh mesh = extrudedGrid();
    const int n = int(mesh.visual.positions.size());
    const VertexWelder welder(mesh.primitives, n);
    int largest = -1;
    for (const auto& p : mesh.primitives)
        for (int id : p.globalIds()) largest = std::max(largest, id);
    ASSERT_GT(largest, n); // the test needs inner ids
    for (int id = 0; id <= largest + 1; ++id) {
        std::vector<int> carriers;
        for (int p = 0; p < int(mesh.primitives.size()); ++p) {
            const auto& ids = mesh.primitives[size_t(p)].globalIds();
            if (std::find(ids.begin(), ids.end(), id) != ids.end()) carriers.push_back(p);
        }
        EXPECT_EQ(welder.primitivesCarrying({id}), carriers) << "id " << id;
        EXPECT_EQ(welder.carries(id), id < n && !carriers.empty()) << "id " << id;
    }
}

TEST(VertexWelder, OtherPrimitivesThanAtConstructionAreRejected) {
    const PhysicalMesh mesh = extrudedGrid();
    const VertexWelder welder(mesh.primitives, int(mesh.visual.positions.size()));
    std::vector<ConvexPolyhedron> fewer(mesh.primitives.begin(), mesh.primitives.end() - 1);
    std::vector<Eigen::Vector3d> positions;
    EXPECT_THROW(welder.weld(fewer, Eigen::Isometry3d::Identity(), positions), std::invalid_argument);
    std::vector<Eigen::Vector3d> flat;
    for (const auto& p : mesh.primitives) flat.insert(flat.end(), p.vertices().begin(), p.vertices().end());
    flat.pop_back();
    EXPECT_THROW(welder.weld(flat, Eigen::Isometry3d::Identity(), positions), std::invalid_argument);
}

TEST(VertexWelder, RemovalsGiveTheWelderOfThePrimitivesLeft) {
    // Primitives leave in rounds (the others closing up in order, as a lattice piece sheds
    // tets): the edited welder is the one built for the primitives left, so its weld gives
    // the same bits, through the rebuild once dead entries outnumber live ones.
    const PhysicalMesh mesh = extrudedGrid(10, 8);
    const int n = int(mesh.visual.positions.size());
    std::vector<ConvexPolyhedron> left = mesh.primitives;
    VertexWelder edited(left, n);
    std::mt19937 rng(11);
    for (const int count : {1, 7, 3, 12, 20, 1, 9, 5, 0, 8}) {
        ASSERT_GT(int(left.size()), count);
        const std::vector<int> removed = someOf(int(left.size()), count, rng);
        left = without(left, removed);
        edited.removePrimitives(left, removed);
        const VertexWelder fresh(left, n);
        SCOPED_TRACE(testing::Message() << left.size() << " primitives left");
        expectSameWelder(edited, fresh, jiggled(left, unsigned(left.size())), n);
    }
    // The first, the last, and all but one.
    for (const bool last : {false, true}) {
        const std::vector<int> removed = {last ? int(left.size()) - 1 : 0};
        left = without(left, removed);
        edited.removePrimitives(left, removed);
        expectSameWelder(edited, VertexWelder(left, n), jiggled(left, 3), n);
    }
    std::vector<int> allButOne;
    for (int p = 1; p < int(left.size()); ++p) allButOne.push_back(p);
    left = without(left, allButOne);
    edited.removePrimitives(left, allButOne);
    expectSameWelder(edited, VertexWelder(left, n), jiggled(left, 4), n);
}

TEST(VertexWelder, RemovalsFollowAFilledWelder) {
    // A welder edited by fillHoles (moved blocks, appended entries, swapped ids), then by a
    // removal: still the welder of the primitives left.
    const PhysicalMesh mesh = extrudedGrid(6, 5);
    const int n = int(mesh.visual.positions.size());
    VertexWelder edited(mesh.primitives, n);
    const std::vector<int> holes = {2, 9, 17};
    const HoleFilling slots = fillHoles(int(mesh.primitives.size()), holes, 1);
    const ConvexPolyhedron& piece = mesh.primitives[size_t(holes[0])]; // a cut piece carrying its ids
    std::vector<ConvexPolyhedron> after(size_t(slots.size), piece);
    const std::vector<int> to = slots.newIndex(int(mesh.primitives.size()), holes);
    for (size_t p = 0; p < to.size(); ++p)
        if (to[p] >= 0) after[size_t(to[p])] = mesh.primitives[p];
    edited.fillHoles(after, holes, slots, {}, n);
    ASSERT_NO_FATAL_FAILURE(expectSameWelder(edited, VertexWelder(after, n), jiggled(after, 1), n));
    const std::vector<int> removed = {0, 5, int(after.size()) - 1};
    const std::vector<ConvexPolyhedron> left = without(after, removed);
    edited.removePrimitives(left, removed);
    expectSameWelder(edited, VertexWelder(left, n), jiggled(left, 2), n);
}

TEST(VertexWelder, TheUncarriedIdsAreListedThroughEveryEdit) {
    // Built with uncarried ids; then a fracture's edit that orphans the ids of the primitives
    // it removes and adds three visual ids that only a piece carries, of which one stays
    // uncarried; then a removal. After each, the list is what carries() says, and a fresh
    // welder's.
    const PhysicalMesh mesh = extrudedGrid(6, 5);
    int n = 0; // past every id, inner ones too: ids from n up are free
    for (const auto& p : mesh.primitives)
        for (int id : p.globalIds()) n = std::max(n, id + 1);
    VertexWelder edited(mesh.primitives, n + 2); // n and n + 1: no primitive carries them
    EXPECT_EQ(edited.uncarried(), (std::vector<int>{n, n + 1}));
    const std::vector<int> holes = {0, 1, 2, 3, 4, 5, 9, 17};
    const HoleFilling slots = fillHoles(int(mesh.primitives.size()), holes, 1);
    const ConvexPolyhedron& source = mesh.primitives[size_t(holes[0])];
    std::vector<int> pieceIds = source.globalIds();
    pieceIds[0] = n + 1; // one of the ids uncarried before
    pieceIds[1] = n + 3; // a new visual id; n + 2 and n + 4 stay uncarried
    const ConvexPolyhedron piece = source.withGlobalIds(pieceIds);
    std::vector<ConvexPolyhedron> after(size_t(slots.size), piece);
    const std::vector<int> to = slots.newIndex(int(mesh.primitives.size()), holes);
    for (size_t p = 0; p < to.size(); ++p)
        if (to[p] >= 0) after[size_t(to[p])] = mesh.primitives[p];
    edited.fillHoles(after, holes, slots, {}, n + 5);
    const VertexWelder fresh(after, n + 5);
    ASSERT_TRUE(fresh.carries(n + 1) && fresh.carries(n + 3) && !fresh.carries(n + 2));
    ASSERT_GT(fresh.uncarried().size(), 3u); // the edit orphaned some of the removed ones' ids
    expectSameWelder(edited, fresh, jiggled(after, 5), n + 5);
    const std::vector<int> removed = {0, 5, int(after.size()) - 1};
    const std::vector<ConvexPolyhedron> left = without(after, removed);
    edited.removePrimitives(left, removed);
    expectSameWelder(edited, VertexWelder(left, n + 5), jiggled(left, 6), n + 5);
}

TEST(VertexWelder, WeldCarriedOnlyByWritesTheIdsARemovalOrphans) {
    // The ids that only the removed primitives carry get weld()'s bits; no other id is written.
    const PhysicalMesh mesh = extrudedGrid(10, 8);
    const int n = int(mesh.visual.positions.size());
    const VertexWelder welder(mesh.primitives, n);
    const std::vector<ConvexPolyhedron> moved = jiggled(mesh.primitives, 21);
    const Eigen::Isometry3d t = Eigen::Translation3d(1, 2, 3) * Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitX());
    std::vector<Eigen::Vector3d> all;
    welder.weld(moved, t, all);
    std::mt19937 rng(5);
    const std::vector<int> only = someOf(int(mesh.primitives.size()), 30, rng);
    const VertexWelder rest(without(mesh.primitives, only), n);
    const Eigen::Vector3d mark(7, 7, 7);
    std::vector<Eigen::Vector3d> some(size_t(n), mark);
    welder.weldCarriedOnlyBy(moved, only, t, some);
    int orphans = 0;
    for (int id = 0; id < n; ++id) {
        const bool orphan = rest.primitivesCarrying({id}).empty();
        orphans += orphan;
        if (orphan) EXPECT_EQ(some[size_t(id)], all[size_t(id)]) << id; // bitwise
        else EXPECT_EQ(some[size_t(id)], mark) << id;
    }
    EXPECT_GE(orphans, 3); // a real test: 30 of 80 quads leave some grid vertices (5 with this seed) to none
    std::vector<Eigen::Vector3d> none;
    welder.weldCarriedOnlyBy(moved, {}, t, none);
    EXPECT_EQ(none.size(), size_t(n)); // grown, nothing written
}

TEST(VertexWelder, BadRemovalsAreRejected) {
    const PhysicalMesh mesh = extrudedGrid();
    const int n = int(mesh.visual.positions.size());
    VertexWelder welder(mesh.primitives, n);
    const std::vector<ConvexPolyhedron> left = without(mesh.primitives, {1});
    EXPECT_THROW(welder.removePrimitives(left, {1, 1}), std::invalid_argument);
    EXPECT_THROW(welder.removePrimitives(left, {3, 1}), std::invalid_argument);
    EXPECT_THROW(welder.removePrimitives(left, {int(mesh.primitives.size())}), std::invalid_argument);
    EXPECT_THROW(welder.removePrimitives(mesh.primitives, {1}), std::invalid_argument); // count
    std::vector<Eigen::Vector3d> positions;
    EXPECT_THROW(welder.weldCarriedOnlyBy(mesh.primitives, {-1}, Eigen::Isometry3d::Identity(), positions),
                 std::invalid_argument);
    // Nothing changed: still the welder it was.
    expectSameWelder(welder, VertexWelder(mesh.primitives, n), mesh.primitives, n);
}
