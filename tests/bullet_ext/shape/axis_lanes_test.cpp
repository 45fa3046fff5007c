// Four axes at once (AxisLanes.h): every lane holds the bits btVector3's own operations give
// for that lane's vectors, and the sampled overlap bound is the full overlap's when the sample
// is every vertex, and at most it otherwise.
#include <shatter/bullet_ext/shape/AxisLanes.h>
#include <shatter/bullet_ext/shape/HullLanes.h>
#include "tests/support/SameBits.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

namespace shatter {
namespace {

using shatter::test::sameBits;

void expectLane(const Vector4& lanes, int l, const btVector3& v) {
    EXPECT_TRUE(sameBits(lanes.x[l], v.x())) << lanes.x[l] << " " << v.x();
    EXPECT_TRUE(sameBits(lanes.y[l], v.y())) << lanes.y[l] << " " << v.y();
    EXPECT_TRUE(sameBits(lanes.z[l], v.z())) << lanes.z[l] << " " << v.z();
}

// Vectors of mixed sizes, as world-space edges and vertices are.
btVector3 randomVector(std::mt19937& rng) {
    std::uniform_real_distribution<float> u(-1.0f, 1.0f), scale(-3.0f, 2.0f);
    const float s = std::pow(10.0f, scale(rng));
    return btVector3(s * u(rng), s * u(rng), s * u(rng));
}

Vector4 lanesOf(const btVector3 (&v)[4]) {
    Vector4 lanes{};
    for (int l = 0; l < 4; ++l) {
        lanes.x[l] = v[l].x();
        lanes.y[l] = v[l].y();
        lanes.z[l] = v[l].z();
    }
    return lanes;
}

TEST(AxisLanes, RotatedIsBulletsMatrixTimesVectorBitForBit) {
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> angle(-3.2f, 3.2f);
    for (int trial = 0; trial < 2000; ++trial) {
        btMatrix3x3 basis;
        basis.setEulerZYX(angle(rng), angle(rng), angle(rng));
        btVector3 v[4];
        for (auto& x : v) x = randomVector(rng);
        const Vector4 turned = rotated(basis, lanesOf(v));
        for (int l = 0; l < 4; ++l) expectLane(turned, l, basis * v[l]);
    }
}

// Vertices placed by a transform four at a time, and a lane spread to all four, as the small
// hulls' test reads them: btTransform * btVector3 bit for bit, a −0 included (axis-aligned
// poses and vectors give zeros of either sign).
TEST(AxisLanes, PlacedAndSpreadAreBulletsTransformTimesVectorBitForBit) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> angle(-3.2f, 3.2f);
    for (int trial = 0; trial < 2000; ++trial) {
        btTransform t(btMatrix3x3::getIdentity(), randomVector(rng));
        if (trial % 4 != 0) t.getBasis().setEulerZYX(angle(rng), angle(rng), angle(rng));
        btVector3 v[4];
        for (auto& x : v) x = randomVector(rng);
        if (trial % 4 == 0) v[trial % 16 / 4].setValue(-0.0f, 0.0f, -0.0f);
        if (trial % 8 == 0) t.setOrigin(btVector3(-0.0f, 0.0f, 0.0f));
        const Vector4 world = placed(t, lanesOf(v));
        for (int l = 0; l < 4; ++l) {
            expectLane(world, l, t * v[l]);
            const Vector4 spreadOut = l == 0 ? spread<0>(world) : l == 1 ? spread<1>(world) : l == 2 ? spread<2>(world) : spread<3>(world);
            for (int m = 0; m < 4; ++m) expectLane(spreadOut, m, t * v[l]);
        }
        const Vector4 same = splat(v[0]);
        for (int m = 0; m < 4; ++m) expectLane(same, m, v[0]);
    }
}

TEST(AxisLanes, CrossNormalizeTurnAndDotAreBulletsBitForBit) {
    std::mt19937 rng(3);
    for (int trial = 0; trial < 2000; ++trial) {
        const btVector3 edge = randomVector(rng), towards = randomVector(rng);
        btVector3 others[4], vertex = randomVector(rng);
        for (auto& o : others) o = randomVector(rng);
        const Vector4 axes = turnedTowards(normalized(cross(splat(edge), lanesOf(others))), towards);
        const Float4 along = dot(splat(vertex), axes);
        for (int l = 0; l < 4; ++l) {
            btVector3 n = edge.cross(others[l]);
            expectLane(cross(splat(edge), lanesOf(others)), l, n);
            n.normalize();
            if (towards.dot(n) < 0) n *= btScalar(-1);
            expectLane(axes, l, n);
            EXPECT_TRUE(sameBits(along[l], vertex.dot(n)));
        }
    }
}

TEST(AxisLanes, TheSampledOverlapIsTheWholeOnesForEveryVertexAndAtMostItForSome) {
    std::mt19937 rng(4);
    for (int trial = 0; trial < 500; ++trial) {
        std::vector<btVector3> a(9), b(7);
        for (auto& v : a) v = randomVector(rng);
        for (auto& v : b) v = randomVector(rng) + btVector3(0.1f, 0, 0);
        btVector3 axes[4];
        for (auto& n : axes) n = randomVector(rng).normalized();
        std::vector<Vector4> laneA, laneB;
        for (const auto& v : a) laneA.push_back(splat(v));
        for (const auto& v : b) laneB.push_back(splat(v));
        const Float4 whole = overlapBelow(lanesOf(axes), {laneA.data(), 9}, {laneB.data(), 7});
        const Float4 some = overlapBelow(lanesOf(axes), {laneA.data() + 2, 4}, {laneB.data() + 1, 3});
        for (int l = 0; l < 4; ++l) {
            btScalar minA = BT_LARGE_FLOAT, maxA = -BT_LARGE_FLOAT, minB = BT_LARGE_FLOAT, maxB = -BT_LARGE_FLOAT;
            for (const auto& v : a) {
                minA = std::min(minA, v.dot(axes[l]));
                maxA = std::max(maxA, v.dot(axes[l]));
            }
            for (const auto& v : b) {
                minB = std::min(minB, v.dot(axes[l]));
                maxB = std::max(maxB, v.dot(axes[l]));
            }
            EXPECT_TRUE(sameBits(whole[l], std::min(maxA - minB, maxB - minA)));
            EXPECT_LE(some[l], whole[l]);
        }
    }
}

TEST(VertexLanes, TheExtentIsTheOneReadVertexByVertexBitForBit) {
    std::mt19937 rng(11);
    for (int trial = 0; trial < 2000; ++trial) {
        const int count = 1 + trial % VertexLanes::kMaxVertices;
        std::vector<btVector3> vertices(static_cast<size_t>(count));
        for (auto& v : vertices) v = randomVector(rng);
        VertexLanes lanes;
        lanes.assign(count, [&](int k) -> const btVector3& { return vertices[static_cast<size_t>(k)]; });
        const btVector3 axis = randomVector(rng).normalized();
        btScalar min = BT_LARGE_FLOAT, max = -BT_LARGE_FLOAT;
        for (const btVector3& v : vertices) {
            min = std::min(min, v.dot(axis));
            max = std::max(max, v.dot(axis));
        }
        btScalar laneMin = 0, laneMax = 0;
        lanes.extentAlong(axis, laneMin, laneMax);
        EXPECT_TRUE(sameBits(laneMin, min)) << count << " vertices: " << laneMin << " " << min;
        EXPECT_TRUE(sameBits(laneMax, max)) << count << " vertices: " << laneMax << " " << max;
    }
}

} // namespace
} // namespace shatter

namespace shatter {
namespace {

// A hull of `count` random vertices (some coordinates −0) and `faces` faces with random normals.
btConvexPolyhedron randomHull(std::mt19937& rng, int count, int faces) {
    btConvexPolyhedron h;
    for (int k = 0; k < count; ++k) h.m_vertices.push_back(k == 1 ? btVector3(-0.0f, 0.0f, -0.0f) : randomVector(rng));
    for (int f = 0; f < faces; ++f) {
        btFace face;
        const btVector3 n = f == 2 ? btVector3(-0.0f, 1.0f, 0.0f) : randomVector(rng).normalized();
        for (int c = 0; c < 3; ++c) face.m_plane[c] = n[c];
        face.m_plane[3] = 1.0f;
        h.m_faces.push_back(face);
    }
    return h;
}

// A hull's lanes: each vertex and face normal in its block's lane with its bits; a short
// vertex block repeats the last vertex, a short face block holds zeros; hulls too big to be
// small keep none.
TEST(HullLanes, HoldTheVerticesAndFaceNormalsBitForBit) {
    std::mt19937 rng(17);
    for (int count = 1; count <= 9; ++count)
        for (const int faces : {0, 4, 5, 6, 12, 13}) {
            const btConvexPolyhedron h = randomHull(rng, count, faces);
            HullLanes lanes;
            lanes.assign(h);
            ASSERT_EQ(lanes.vertexBlocks, count <= 8 ? (count + 3) / 4 : 0);
            for (int k = 0; k < 4 * lanes.vertexBlocks; ++k)
                expectLane(lanes.vertices[k / 4], k % 4, h.m_vertices[std::min(k, count - 1)]);
            ASSERT_EQ(lanes.faceBlocks, faces <= 12 ? (faces + 3) / 4 : 0);
            for (int f = 0; f < 4 * lanes.faceBlocks; ++f) {
                const btScalar* p = h.m_faces[std::min(f, faces - 1)].m_plane;
                expectLane(lanes.faceNormals[f / 4], f % 4, f < faces ? btVector3(p[0], p[1], p[2]) : btVector3(0, 0, 0));
            }
        }
    // Kept only by a LanedPolyhedron, and refreshed on request.
    LanedPolyhedron laned;
    static_cast<btConvexPolyhedron&>(laned) = randomHull(rng, 4, 4);
    laned.refreshLanes();
    const btConvexPolyhedron& asPlain = laned;
    ASSERT_EQ(keptLanes(asPlain), &laned.lanes());
    expectLane(keptLanes(asPlain)->vertices[0], 3, laned.m_vertices[3]);
    EXPECT_EQ(keptLanes(randomHull(rng, 4, 4)), nullptr);
}

// Two small hulls' overlap along four axes from their vertex blocks (placed as the test places
// them): each lane is min(maxA − minB, maxB − minA) read vertex by vertex with btVector3::dot.
TEST(AxisLanes, TheBlockOverlapIsTheOneReadVertexByVertexBitForBit) {
    std::mt19937 rng(23);
    for (int trial = 0; trial < 1000; ++trial) {
        const btConvexPolyhedron a = randomHull(rng, 1 + trial % 8, 0), b = randomHull(rng, 1 + trial / 8 % 8, 0);
        HullLanes la, lb;
        la.assign(a);
        lb.assign(b);
        btVector3 axis[4];
        for (auto& n : axis) n = randomVector(rng).normalized();
        const Float4 overlap = blockOverlap(lanesOf(axis), la.vertices, la.vertexBlocks, lb.vertices, lb.vertexBlocks);
        for (int l = 0; l < 4; ++l) {
            btScalar minA = BT_LARGE_FLOAT, maxA = -BT_LARGE_FLOAT, minB = BT_LARGE_FLOAT, maxB = -BT_LARGE_FLOAT;
            for (int k = 0; k < a.m_vertices.size(); ++k) {
                minA = std::min(minA, a.m_vertices[k].dot(axis[l]));
                maxA = std::max(maxA, a.m_vertices[k].dot(axis[l]));
            }
            for (int k = 0; k < b.m_vertices.size(); ++k) {
                minB = std::min(minB, b.m_vertices[k].dot(axis[l]));
                maxB = std::max(maxB, b.m_vertices[k].dot(axis[l]));
            }
            const btScalar d0 = maxA - minB, d1 = maxB - minA;
            EXPECT_TRUE(sameBits(overlap[l], d0 < d1 ? d0 : d1)) << "trial " << trial << ", lane " << l;
        }
    }
}

} // namespace
} // namespace shatter
