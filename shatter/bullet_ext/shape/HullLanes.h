#pragma once
// A small hull's vertices and face planes (normals and offsets, its own frame) already in lanes
// (AxisLanes.h), as the separating-axis test of two small hulls reads them
// (PolyhedronContacts.cpp, FragmentPairAlgorithm.cpp's separating face). A group's
// leaf hulls keep them (LanedPolyhedron, built when the hull's features are set or moved), so
// the test, run for every new leaf pair, does not put coordinates into lanes one by one.
#include <shatter/bullet_ext/shape/AxisLanes.h>

#include <BulletCollision/CollisionShapes/btConvexPolyhedron.h>

#include <algorithm>
#include <atomic>
#include <typeinfo>

namespace shatter {

struct HullLanes {
    static constexpr int kMaxVertices = VertexLanes::kMaxVertices; // the small hulls' limit
    static constexpr int kMaxFaces = 12;                            // what a convex hull of 8 vertices can have
    // Four vertices a block (x, y, z of vertex 4b + l in lane l); a short block repeats the
    // last vertex, which changes no extent. Set only for a hull of at most kMaxVertices.
    Vector4 vertices[kMaxVertices / 4];
    int vertexBlocks = 0;
    // Four face normals (the planes' first three coordinates) a block, zero in spare lanes;
    // faceBlocks 0 when the hull has more than kMaxFaces faces (then read from the hull).
    Vector4 faceNormals[kMaxFaces / 4];
    Float4 faceOffsets[kMaxFaces / 4]; // the planes' fourth coordinates, zero in spare lanes
    int faceBlocks = 0;

    // Copies h's vertices and face planes (their bits: a −0 stays −0).
    void assign(const btConvexPolyhedron& h) {
        const int count = h.m_vertices.size();
        vertexBlocks = count <= kMaxVertices ? (count + 3) / 4 : 0;
        for (int k = 0; k < 4 * vertexBlocks; ++k) {
            const btVector3& v = h.m_vertices[k < count ? k : count - 1];
            vertices[k / 4].x[k % 4] = v.x();
            vertices[k / 4].y[k % 4] = v.y();
            vertices[k / 4].z[k % 4] = v.z();
        }
        const int faces = h.m_faces.size();
        faceBlocks = faces <= kMaxFaces ? (faces + 3) / 4 : 0;
        for (int f = 0; f < 4 * faceBlocks; ++f) {
            const btScalar* p = h.m_faces[f < faces ? f : 0].m_plane;
            const bool spare = f >= faces;
            faceNormals[f / 4].x[f % 4] = spare ? btScalar(0) : p[0];
            faceNormals[f / 4].y[f % 4] = spare ? btScalar(0) : p[1];
            faceNormals[f / 4].z[f % 4] = spare ? btScalar(0) : p[2];
            faceOffsets[f / 4][f % 4] = spare ? btScalar(0) : p[3];
        }
    }
};

// Polyhedral features that keep their lanes. Whoever changes the features calls refreshLanes.
class LanedPolyhedron : public btConvexPolyhedron {
public:
    BT_DECLARE_ALIGNED_ALLOCATOR();
    void refreshLanes() {
        lanes_.assign(*this);
        ownFront_.store(-1.0, std::memory_order_relaxed);
    }
    const HullLanes& lanes() const { return lanes_; }
    // How far the hull's own vertices lie in front of its face planes, at most (≥ 0; the planes'
    // rounding, or a merged face's vertices off its plane): a face plane that has the other hull
    // in front of it by more than this (and the rounding) also separates the two hulls' spans
    // along its normal, as Bullet's separating-axis test reads them. Found when first asked
    // (a soft body's step moves its hulls every step, and never asks).
    double ownFront() const {
        double front = ownFront_.load(std::memory_order_relaxed);
        if (front >= 0) return front;
        front = 0;
        for (int f = 0; f < m_faces.size(); ++f) {
            const btScalar* p = m_faces[f].m_plane;
            for (int v = 0; v < m_vertices.size(); ++v) {
                const btVector3& x = m_vertices[v];
                front = std::max(front, double(p[0]) * double(x.x()) + double(p[1]) * double(x.y()) +
                                            double(p[2]) * double(x.z()) + double(p[3]));
            }
        }
        ownFront_.store(front, std::memory_order_relaxed);
        return front;
    }

private:
    HullLanes lanes_;
    mutable std::atomic<double> ownFront_{-1.0}; // < 0: not found yet
};

// h's kept lanes, or null when h keeps none (a plain btConvexPolyhedron: Bullet's own hulls).
inline const HullLanes* keptLanes(const btConvexPolyhedron& h) {
    return typeid(h) == typeid(LanedPolyhedron) ? &static_cast<const LanedPolyhedron&>(h).lanes() : nullptr;
}

// h as a LanedPolyhedron, or null.
inline const LanedPolyhedron* lanedPolyhedron(const btConvexPolyhedron& h) {
    return typeid(h) == typeid(LanedPolyhedron) ? &static_cast<const LanedPolyhedron&>(h) : nullptr;
}

} // namespace shatter
