// A lattice piece that sheds tets keeps its body (VisualBody::removePrimitives): its welder is
// edited rather than built again, and only the visual vertices the removal leaves to no tet are
// welded before it. The visual mesh after every shrink must be the one of a new welder of the
// tets left, bit for bit: positions, vertex ids and faces.
#include <shatter/bullet_ext/Convert.h>
#include <shatter/bullet_ext/VisualBody.h>
#include <shatter/bullet_ext/lattice/LatticeBody.h>
#include <shatter/plugin/common/InputError.h>
#include <shatter/plugin/lattice/TetGenerators.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

namespace shatter {
namespace {

// What removePrimitives did before it edited its welder: a weld of every primitive at the
// body's pose before the removal (the vertices no tet keeps stay there), a new welder of the
// primitives left, and a weld of those at the next visualMesh().
struct Reference {
    std::vector<geometry::ConvexPolyhedron> primitives; // the body's, in its shape frame
    int ids = 0;
    std::vector<Eigen::Vector3d> positions;

    void weld(const Eigen::Isometry3d& shapeToWorld) {
        geometry::VertexWelder(primitives, ids).weld(primitives, shapeToWorld, positions);
    }
    void remove(const std::vector<int>& gone) {
        std::vector<geometry::ConvexPolyhedron> left;
        for (size_t p = 0; p < primitives.size(); ++p)
            if (!std::binary_search(gone.begin(), gone.end(), int(p))) left.push_back(primitives[p]);
        primitives = std::move(left);
    }
};

std::vector<std::vector<int>> asVectors(const geometry::FaceList& faces) {
    std::vector<std::vector<int>> out;
    for (const auto face : faces) out.emplace_back(face.begin(), face.end());
    return out;
}

void shrinkAndCompare(bool dynamic) {
    lattice::GeneratorOptions g;
    g.jitter = 0.2;
    g.seed = 3;
    LatticeSettings settings;
    settings.name = "block";
    LatticeBody lattice(0, lattice::tetBox({0.6, 0.5, 0.4}, {6, 5, 4}, g), settings);
    std::vector<int> tets(size_t(lattice.tetCount()));
    for (int t = 0; t < lattice.tetCount(); ++t) tets[size_t(t)] = t;
    const btTransform start(btQuaternion(btVector3(0, 1, 0), 0.3f), btVector3(1, 2, 3));
    VisualBody body(1, lattice.physicalMesh(tets, "block"), lattice.bodySettings(!dynamic), start);
    const Eigen::Isometry3d meshToShape = body.meshToBody(); // the shape keeps the frame it was built in
    Reference reference{body.shapePrimitives(), int(body.physicalMesh().visual.positions.size()), {}};
    bool reframed = false;
    auto shapeToWorld = [&] {
        const Eigen::Isometry3d bodyFromShape =
            reframed ? Eigen::Isometry3d(body.meshToBody() * meshToShape.inverse()) : Eigen::Isometry3d::Identity();
        return Eigen::Isometry3d(toEigen(body.rigidBody().getWorldTransform()) * bodyFromShape);
    };
    std::mt19937 rng(7);
    for (int round = 0; round < 8; ++round) {
        SCOPED_TRACE(testing::Message() << "round " << round << ", " << tets.size() << " tets");
        // Moved since the last weld (or, every third round, welded where it is).
        const btTransform pose(btQuaternion(btVector3(1, 0.5f, 0).normalized(), 0.2f * float(round)),
                               btVector3(0.1f * float(round), 2, -0.3f * float(round)));
        body.rigidBody().setWorldTransform(pose);
        if (round % 3 == 2) {
            body.visualMesh();
            reference.weld(shapeToWorld());
        }
        // Every tet around a vertex (which then no tet carries) and a few anywhere.
        std::vector<int> removed;
        const auto& primitives = body.physicalMesh().primitives;
        const int orphan = primitives[rng() % primitives.size()].globalIds()[size_t(rng() % 4)];
        for (int i = 0; i < int(primitives.size()); ++i) {
            const auto& ids = primitives[size_t(i)].globalIds();
            if (std::find(ids.begin(), ids.end(), orphan) != ids.end()) removed.push_back(i);
        }
        for (int k = 0; k < round * 3; ++k) removed.push_back(int(rng() % tets.size()));
        if (round == 4) std::reverse(removed.begin(), removed.end()); // any order, repeats allowed
        std::vector<int> gone = removed;
        std::sort(gone.begin(), gone.end());
        gone.erase(std::unique(gone.begin(), gone.end()), gone.end());
        std::vector<int> kept;
        for (int i = 0; i < int(tets.size()); ++i)
            if (!std::binary_search(gone.begin(), gone.end(), i)) kept.push_back(tets[size_t(i)]);
        const geometry::FaceList faces = lattice.surfaceIn(body.physicalMesh(), tets, kept);

        reference.weld(shapeToWorld());
        reference.remove(gone);
        body.removePrimitives(removed, faces, lattice.massOf(kept));
        reframed = reframed || dynamic;
        tets = kept;

        if (round % 2 == 1) // moved again before anyone looks
            body.rigidBody().setWorldTransform(
                btTransform(btQuaternion(btVector3(0, 0, 1), 0.1f * float(round)), btVector3(-1, 0.5f, 0)));
        const geometry::VisualMesh& visual = body.visualMesh();
        reference.weld(shapeToWorld());
        ASSERT_EQ(body.shapePrimitives().size(), reference.primitives.size());
        ASSERT_EQ(visual.positions.size(), reference.positions.size());
        for (size_t id = 0; id < visual.positions.size(); ++id)
            ASSERT_EQ(visual.positions[id], reference.positions[id]) << "visual vertex " << id; // bitwise
        EXPECT_EQ(visual.faces, asVectors(faces));
        EXPECT_EQ(body.physicalMesh().visual.faces, visual.faces);
        EXPECT_TRUE(visual.crackFace.empty());
    }
}

TEST(LatticeShrink, AStaticPieceWeldsAsANewWelderOfTheTetsLeft) { shrinkAndCompare(false); }

TEST(LatticeShrink, AMovingPieceWeldsAsANewWelderOfTheTetsLeft) { shrinkAndCompare(true); }

TEST(LatticeShrink, ABadIndexIsRejectedBeforeAnythingChanges) {
    LatticeSettings settings;
    LatticeBody lattice(0, lattice::tetBox({0.2, 0.2, 0.2}, {2, 2, 2}), settings);
    std::vector<int> tets(size_t(lattice.tetCount()));
    for (int t = 0; t < lattice.tetCount(); ++t) tets[size_t(t)] = t;
    VisualBody body(1, lattice.physicalMesh(tets, "block"), lattice.bodySettings(true), btTransform::getIdentity());
    const std::vector<Eigen::Vector3d> before = body.visualMesh().positions;
    const geometry::FaceList faces = lattice.surfaceIn(body.physicalMesh(), tets, tets);
    EXPECT_THROW(body.removePrimitives({0, lattice.tetCount()}, faces, lattice.massOf(tets)), InputError);
    EXPECT_THROW(body.removePrimitives({-1}, faces, lattice.massOf(tets)), InputError);
    geometry::FaceList beyond = faces;
    const int ids = int(before.size());
    beyond.add(std::vector<int>{0, 1, ids});
    EXPECT_THROW(body.removePrimitives({0}, beyond, lattice.massOf(tets)), InputError);
    EXPECT_EQ(body.physicalMesh().primitives.size(), tets.size());
    EXPECT_EQ(body.visualMesh().positions, before);
}

} // namespace
} // namespace shatter
