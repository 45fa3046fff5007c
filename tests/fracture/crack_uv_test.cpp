// Planar texture coordinates of crack faces: no stretch, and both sides of a crack alike.
#include "FractureFixtures.h"

#include <shatter/plugin/fracture/CrackUv.h>
#include <shatter/plugin/fracture/FractureMesh.h>

#include <gtest/gtest.h>

#include <map>

using namespace shatter;
using namespace shatter::fracture;

TEST(CrackUv, CrackFacesMapWithoutStretchAndBothSidesOfACrackAlike) {
    // Four unit cubes broken by a jittered grid pattern: every crack lies between two
    // fragments. On every crack face the texture coordinates keep the distances between its
    // vertices (a planar map in metres), and the partner face across the crack (the same
    // vertices wound the other way) gives each shared vertex the same coordinates.
    const FractureResult r = test::fourCubesBrokenByGrid();
    ASSERT_EQ(r.remainder, -1);
    std::map<int, std::vector<Eigen::Vector2d>> uvAt; // fracture-wide id → every uv given to it
    int faces = 0;
    for (size_t i = 0; i < r.pieces.size(); ++i) {
        const auto& visual = r.pieces[i].visual;
        for (size_t f = 0; f < visual.faces.size(); ++f) {
            if (!visual.isCrackFace(f)) continue;
            const auto& face = visual.faces[f];
            const auto uv = crackFaceUvs(visual.positions, face);
            ASSERT_EQ(uv.size(), face.size());
            for (size_t a = 0; a < face.size(); ++a) {
                for (size_t b = a + 1; b < face.size(); ++b) {
                    const double d = (visual.positions[size_t(face[a])] - visual.positions[size_t(face[b])]).norm();
                    EXPECT_NEAR((uv[a] - uv[b]).norm(), d, 1e-9) << "piece " << i << ", face " << f;
                }
                uvAt[r.sharedIds[i][size_t(face[a])]].push_back(uv[a]);
            }
            ++faces;
        }
    }
    EXPECT_GT(faces, 16);
    // A vertex on several cracks has one uv per crack plane; across one crack both sides agree,
    // so every uv a vertex gets is given at least twice.
    int shared = 0;
    for (const auto& [id, uvs] : uvAt)
        for (const auto& uv : uvs) {
            int same = 0;
            for (const auto& other : uvs) same += (other - uv).norm() < 1e-12;
            EXPECT_GE(same, 2) << "id " << id;
            shared += same >= 2;
        }
    EXPECT_GT(shared, 32);
}

TEST(CrackUv, TheMapDependsOnThePlaneNotOnTheWinding) {
    const std::vector<Eigen::Vector3d> p{{0, 0, 1}, {2, 0, 1}, {2, 1, 1.5}, {0, 1, 1.5}};
    const auto forward = crackFaceUvs(p, {0, 1, 2, 3});
    const auto backward = crackFaceUvs(p, {3, 2, 1, 0});
    for (int k = 0; k < 4; ++k) EXPECT_LT((forward[size_t(k)] - backward[size_t(3 - k)]).norm(), 1e-15);
    EXPECT_NEAR((forward[1] - forward[0]).norm(), 2.0, 1e-15);
}
