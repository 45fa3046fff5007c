#pragma once
// Exact comparison of two group shapes (or two child hulls): everything a collision or query
// reads. For shapes reached by different paths that must come out the same bit for bit.
#include <shatter/bullet_ext/shape/GroupShape.h>

#include <BulletCollision/CollisionShapes/btConvexPolyhedron.h>
#include <gtest/gtest.h>

#include <utility>
#include <vector>

namespace shatter::test {

// Two hulls' Bullet features compared exactly, all but the inner box (m_extents), which a
// hull built by another path may reach by other steps (ConvexHullOfPoints).
inline void expectSameFeaturesButTheInnerBox(const btConvexPolyhedron& pa, const btConvexPolyhedron& pb) {
    ASSERT_EQ(pa.m_vertices.size(), pb.m_vertices.size());
    for (int k = 0; k < pa.m_vertices.size(); ++k) EXPECT_EQ(pa.m_vertices[k], pb.m_vertices[k]) << "vertex " << k;
    ASSERT_EQ(pa.m_faces.size(), pb.m_faces.size());
    for (int f = 0; f < pa.m_faces.size(); ++f) {
        for (int c = 0; c < 4; ++c) EXPECT_EQ(pa.m_faces[f].m_plane[c], pb.m_faces[f].m_plane[c]) << "face " << f;
        ASSERT_EQ(pa.m_faces[f].m_indices.size(), pb.m_faces[f].m_indices.size()) << "face " << f;
        for (int k = 0; k < pa.m_faces[f].m_indices.size(); ++k)
            EXPECT_EQ(pa.m_faces[f].m_indices[k], pb.m_faces[f].m_indices[k]) << "face " << f;
    }
    ASSERT_EQ(pa.m_uniqueEdges.size(), pb.m_uniqueEdges.size());
    for (int e = 0; e < pa.m_uniqueEdges.size(); ++e) EXPECT_EQ(pa.m_uniqueEdges[e], pb.m_uniqueEdges[e]) << "edge " << e;
    EXPECT_EQ(pa.m_localCenter, pb.m_localCenter);
    EXPECT_EQ(pa.m_radius, pb.m_radius);
    EXPECT_EQ(pa.mC, pb.mC);
    EXPECT_EQ(pa.mE, pb.mE);
}

// The hull's points and Bullet features (what setPrimitivePoses writes and the inner sphere
// it keeps), compared exactly.
inline void expectSameHull(const btConvexHullShape& a, const btConvexHullShape& b) {
    ASSERT_EQ(a.getNumPoints(), b.getNumPoints());
    for (int k = 0; k < a.getNumPoints(); ++k) EXPECT_EQ(a.getUnscaledPoints()[k], b.getUnscaledPoints()[k]);
    EXPECT_EQ(a.getMargin(), b.getMargin());
    expectSameFeaturesButTheInnerBox(*a.getConvexPolyhedron(), *b.getConvexPolyhedron());
    EXPECT_EQ(a.getConvexPolyhedron()->m_extents, b.getConvexPolyhedron()->m_extents);
    btVector3 loA, hiA, loB, hiB;
    a.getAabb(btTransform::getIdentity(), loA, hiA);
    b.getAabb(btTransform::getIdentity(), loB, hiB);
    EXPECT_EQ(loA, loB);
    EXPECT_EQ(hiA, hiB);
}

// The pairs a tree reports, in its order (the tree's shape and boxes as queries see them).
inline std::vector<std::pair<int, int>> treePairs(const geometry::AabbTree& tree) {
    std::vector<std::pair<int, int>> pairs;
    tree.selfPairs([&](int a, int b) { pairs.emplace_back(a, b); });
    return pairs;
}

// Everything of two shapes a collision or query reads, compared exactly.
inline void expectSameShape(const GroupShape& a, const GroupShape& b) {
    ASSERT_EQ(a.primitiveCount(), b.primitiveCount());
    for (int i = 0; i < a.primitiveCount(); ++i) {
        const geometry::ConvexPolyhedron &p = a.primitives()[size_t(i)], &q = b.primitives()[size_t(i)];
        EXPECT_EQ(p.vertices(), q.vertices());
        EXPECT_EQ(p.faces(), q.faces());
        for (size_t f = 0; f < p.planes().size(); ++f) {
            EXPECT_EQ(p.planes()[f].normal, q.planes()[f].normal);
            EXPECT_EQ(p.planes()[f].offset, q.planes()[f].offset);
        }
        EXPECT_EQ(p.bounds().min, q.bounds().min);
        EXPECT_EQ(p.bounds().max, q.bounds().max);
        expectSameHull(a.child(i), b.child(i));
    }
    EXPECT_EQ(treePairs(a.tree()), treePairs(b.tree()));
    EXPECT_EQ(treePairs(a.contactTree()), treePairs(b.contactTree()));
    EXPECT_EQ(a.tree().bounds().min, b.tree().bounds().min);
    EXPECT_EQ(a.contactTree().bounds().max, b.contactTree().bounds().max);
    EXPECT_EQ(a.contactSlack(), b.contactSlack());
    EXPECT_EQ(a.getMargin(), b.getMargin());
    EXPECT_EQ(a.contactPerPrimitive(), b.contactPerPrimitive());
    EXPECT_EQ(a.revision(), b.revision());
    btVector3 lo, hi, freshLo, freshHi;
    a.getAabb(btTransform::getIdentity(), lo, hi);
    b.getAabb(btTransform::getIdentity(), freshLo, freshHi);
    EXPECT_EQ(lo, freshLo);
    EXPECT_EQ(hi, freshHi);
}

} // namespace shatter::test
