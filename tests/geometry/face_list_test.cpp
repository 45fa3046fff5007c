// FaceList::fromFlat and the clipper's polyhedron built from flat faces (event16b): the faces
// copied at once must be the list add() builds face by face, and a flat face dropped anywhere
// (first, middle, last) must leave the polyhedron createTrusted makes of the kept faces.
#include <shatter/plugin/geometry/ConvexPolyhedron.h>
#include <shatter/plugin/geometry/FaceList.h>
#include "tests/support/SamePolyhedron.h"

#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

using namespace shatter::geometry;

namespace {

const std::vector<std::vector<int>> kCubeFaces = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4},
                                                   {2, 3, 7, 6}, {1, 2, 6, 5}, {0, 4, 7, 3}};

std::vector<Eigen::Vector3d> cubeVertices() {
    const Eigen::Isometry3d tilt = Eigen::Translation3d(0.3, -1.7, 2.1) *
                                   Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized());
    std::vector<Eigen::Vector3d> v = {{0, 0, 0}, {1, 0, 0}, {1, 2, 0}, {0, 2, 0},
                                      {0, 0, 0.5}, {1, 0, 0.5}, {1, 2, 0.5}, {0, 2, 0.5}};
    for (auto& p : v) p = tilt * p;
    return v;
}

} // namespace

TEST(FaceList, FromFlatIsTheListAddedFaceByFace) {
    std::vector<int> start{0}, indices;
    FaceList added;
    for (const auto& face : kCubeFaces) {
        indices.insert(indices.end(), face.begin(), face.end());
        start.push_back(int(indices.size()));
        added.add(face);
    }
    const FaceList flat = FaceList::fromFlat(start, indices);
    EXPECT_EQ(flat, added);
    ASSERT_EQ(flat.size(), kCubeFaces.size());
    for (size_t f = 0; f < kCubeFaces.size(); ++f)
        EXPECT_EQ(std::vector<int>(flat[f].begin(), flat[f].end()), kCubeFaces[f]);
    EXPECT_TRUE(FaceList::fromFlat(std::vector<int>{0}, {}).empty());
    EXPECT_TRUE(FaceList::fromFlat({}, {}).empty());
}

TEST(FaceList, StartsAreWhereEachFaceBegins) {
    EXPECT_TRUE(FaceList().starts().empty());
    const FaceList list(kCubeFaces);
    ASSERT_EQ(list.starts().size(), list.size() + 1);
    EXPECT_EQ(list.starts().front(), 0);
    EXPECT_EQ(size_t(list.starts().back()), list.indices().size());
    for (size_t f = 0; f < list.size(); ++f) {
        EXPECT_EQ(list[f].data(), list.indices().data() + list.starts()[f]);
        EXPECT_EQ(list[f].size(), size_t(list.starts()[f + 1] - list.starts()[f]));
    }
}

TEST(FaceList, FromFlatRejectsStartsThatDoNotCoverTheIndices) {
    const std::vector<int> indices{0, 1, 2, 2, 1, 3};
    EXPECT_THROW(FaceList::fromFlat(std::vector<int>{1, 3, 6}, indices), std::invalid_argument);
    EXPECT_THROW(FaceList::fromFlat(std::vector<int>{0, 3, 5}, indices), std::invalid_argument);
    EXPECT_THROW(FaceList::fromFlat({}, indices), std::invalid_argument);
}

// A collinear face (an edge's midpoint between its ends) put first, between faces, last, or
// nowhere: the kept faces, planes, mass and bounds are createTrusted's bit for bit.
TEST(ConvexPolyhedron, TrustedFromFlatFacesDropsAFlatFaceWhereverItIs) {
    std::vector<Eigen::Vector3d> vertices = cubeVertices();
    vertices.push_back(0.5 * (vertices[0] + vertices[3])); // on the edge 3-0 of face 0
    std::vector<int> ids(vertices.size());
    for (size_t i = 0; i < ids.size(); ++i) ids[i] = int(10 + i);
    const ConvexPolyhedron plain = ConvexPolyhedron::createTrusted(vertices, FaceList(kCubeFaces), ids);
    for (int at : {-1, 0, 3, 6}) {
        SCOPED_TRACE(at);
        std::vector<int> start{0}, indices;
        for (int f = 0; f <= 6; ++f) {
            if (f == at) {
                indices.insert(indices.end(), {3, 8, 0});
                start.push_back(int(indices.size()));
            }
            if (f < 6) {
                indices.insert(indices.end(), kCubeFaces[size_t(f)].begin(), kCubeFaces[size_t(f)].end());
                start.push_back(int(indices.size()));
            }
        }
        const ConvexPolyhedron clipped = ConvexPolyhedron::createTrustedDroppingFlatFaces(vertices, start, indices, ids);
        shatter::test::expectSamePolyhedron(clipped, plain);
    }
    EXPECT_NEAR(plain.volume(), 1.0, 1e-12);
}
