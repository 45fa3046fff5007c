#pragma once
// Four axes of a separating-axis test at once (PolyhedronContacts.cpp): the edge-pair axes
// and the vertices' projections on them, lane by lane, with the float operations of
// btVector3's cross, normalize and dot in the same order. Each lane therefore holds the bits
// the one-axis code computes (Bullet's vector is plain floats on this platform: no reordering,
// and no fused multiply-add: PolyhedronContacts.cpp is compiled with -ffp-contract=off), so a
// bound proven from the lanes holds for that code exactly.
#include <LinearMath/btMatrix3x3.h>
#include <LinearMath/btTransform.h>
#include <LinearMath/btVector3.h>

#include <cmath>

namespace shatter {

// Four floats operated on lane by lane (GCC's vector extension: one SSE register).
using Float4 = float __attribute__((vector_size(4 * sizeof(float))));

// Four vectors, one a lane.
struct Vector4 {
    Float4 x, y, z;
};

// The same vector in every lane (a copy: a −0 stays −0, which adding to zero would not keep).
inline Vector4 splat(const btVector3& v) {
    const float x = v.x(), y = v.y(), z = v.z();
    return {Float4{x, x, x, x}, Float4{y, y, y, y}, Float4{z, z, z, z}};
}

// btVector3::cross, lane by lane.
inline Vector4 cross(const Vector4& a, const Vector4& b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

// btVector3::dot, lane by lane.
inline Float4 dot(const Vector4& a, const Vector4& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

// btMatrix3x3 * btVector3 (a dot product with each row), lane by lane.
inline Vector4 rotated(const btMatrix3x3& basis, const Vector4& v) {
    return {dot(splat(basis[0]), v), dot(splat(basis[1]), v), dot(splat(basis[2]), v)};
}

// btTransform * btVector3 (the rows' dot products, then the origin), lane by lane.
inline Vector4 placed(const btTransform& t, const Vector4& v) {
    const Vector4 turned = rotated(t.getBasis(), v);
    const btVector3& o = t.getOrigin();
    return {turned.x + o.x(), turned.y + o.y(), turned.z + o.z()};
}

// btVector3::normalize (divides by its length as one multiplication by the reciprocal),
// lane by lane. A zero lane gives NaNs, as Bullet's would.
inline Vector4 normalized(const Vector4& v) {
    Float4 length = dot(v, v);
    for (int l = 0; l < 4; ++l) length[l] = std::sqrt(length[l]); // no vector square root in the extension
    const Float4 inverse = Float4{1, 1, 1, 1} / length;
    return {v.x * inverse, v.y * inverse, v.z * inverse};
}

// The lanes' vectors turned to point along `towards` (negated, which is exact, where their
// dot product with it is negative), as the one-axis code turns an axis from b to a.
inline Vector4 turnedTowards(const Vector4& v, const btVector3& towards) {
    const auto negative = dot(splat(towards), v) < Float4{};
    return {negative ? -v.x : v.x, negative ? -v.y : v.y, negative ? -v.z : v.z};
}

// The least and the greatest of four lanes (__builtin_shufflevector: GCC 12 and clang alike).
inline float lowest(Float4 p) {
    Float4 q = __builtin_shufflevector(p, p, 2, 3, 0, 1);
    p = q < p ? q : p;
    q = __builtin_shufflevector(p, p, 1, 0, 3, 2);
    p = q < p ? q : p;
    return p[0];
}
inline float highest(Float4 p) {
    Float4 q = __builtin_shufflevector(p, p, 2, 3, 0, 1);
    p = q > p ? q : p;
    q = __builtin_shufflevector(p, p, 1, 0, 3, 2);
    p = q > p ? q : p;
    return p[0];
}

// A small hull's vertices (up to eight: a lattice's tet, a box), one a lane in blocks of four,
// projected on an axis all at once. Each lane's projection has btVector3::dot's bits, so the
// extent (the least and greatest projection, which no order of reading changes) is the one
// read vertex by vertex. A short block repeats a vertex, which changes no extent.
class VertexLanes {
public:
    static constexpr int kMaxVertices = 8;
    // `count` (1 to kMaxVertices) vertices, vertexAt(k) the k-th.
    template <typename VertexAt>
    void assign(int count, const VertexAt& vertexAt) {
        blocks_ = (count + 3) / 4;
        for (int k = 0; k < 4 * blocks_; ++k) {
            const btVector3& v = vertexAt(k < count ? k : count - 1);
            block_[k / 4].x[k % 4] = v.x();
            block_[k / 4].y[k % 4] = v.y();
            block_[k / 4].z[k % 4] = v.z();
        }
    }
    // The least and greatest of vertex.dot(n) over the vertices.
    void extentAlong(const btVector3& n, btScalar& min, btScalar& max) const {
        const Vector4 axis = splat(n);
        Float4 low = dot(block_[0], axis), high = low;
        if (blocks_ > 1) {
            const Float4 p = dot(block_[1], axis);
            low = p < low ? p : low;
            high = p > high ? p : high;
        }
        min = lowest(low);
        max = highest(high);
    }

private:
    Vector4 block_[kMaxVertices / 4];
    int blocks_ = 0;
};

// Lane l of each coordinate in every lane: a block's vertex l (in blocks of four vertices, one
// a lane) spread to be projected on four axes at once.
template <int l>
inline Vector4 spread(const Vector4& v) {
    return {__builtin_shufflevector(v.x, v.x, l, l, l, l), __builtin_shufflevector(v.y, v.y, l, l, l, l),
            __builtin_shufflevector(v.z, v.z, l, l, l, l)};
}

// Along four axes (lanes), the least and greatest vertex · axis over vertices given in blocks
// of four (one a lane; a short block repeats a vertex, which changes no extent), each
// projection with btVector3::dot's bits, so each lane is what the one-axis code computes.
inline void extentAlongAxes(const Vector4& axes, const Vector4* blocks, int count, Float4& low, Float4& high) {
    low = Float4{} + BT_LARGE_FLOAT;
    high = -low;
    const auto take = [&](const Vector4& vertex) {
        const Float4 p = dot(vertex, axes);
        low = p < low ? p : low;
        high = p > high ? p : high;
    };
    for (int k = 0; k < count; ++k) {
        take(spread<0>(blocks[k]));
        take(spread<1>(blocks[k]));
        take(spread<2>(blocks[k]));
        take(spread<3>(blocks[k]));
    }
}

// Along four unit axes (lanes), the overlap min(maxA − minB, maxB − minA) of two small hulls
// whose vertices are given in blocks of four (extentAlongAxes).
inline Float4 blockOverlap(const Vector4& axes, const Vector4* a, int blocksA, const Vector4* b, int blocksB) {
    Float4 lowA, highA, lowB, highB;
    extentAlongAxes(axes, a, blocksA, lowA, highA);
    extentAlongAxes(axes, b, blocksB, lowB, highB);
    const Float4 d0 = highA - lowB, d1 = highB - lowA;
    return d0 < d1 ? d0 : d1;
}

// Some of a hull's vertices, each in every lane, read by overlapBelow.
struct Sample {
    const Vector4* vertices;
    int count;
};

// Along four unit axes (lanes), a lower bound of the overlap of two hulls, from samples of
// their vertices: the smaller of maxA − minB and maxB − minA over the sampled vertices only.
// A sample's extent lies within the whole hull's, and float rounding is monotonic, so each
// difference is at most the one the whole hulls give in the same arithmetic.
inline Float4 overlapBelow(const Vector4& axis, const Sample& a, const Sample& b) {
    const Float4 large = Float4{} + BT_LARGE_FLOAT;
    Float4 lowA = large, highA = -large, lowB = large, highB = -large;
    for (int k = 0; k < a.count; ++k) {
        const Float4 p = dot(a.vertices[k], axis);
        lowA = p < lowA ? p : lowA;
        highA = p > highA ? p : highA;
    }
    for (int k = 0; k < b.count; ++k) {
        const Float4 p = dot(b.vertices[k], axis);
        lowB = p < lowB ? p : lowB;
        highB = p > highB ? p : highB;
    }
    const Float4 d0 = highA - lowB, d1 = highB - lowA;
    return d0 < d1 ? d0 : d1;
}

} // namespace shatter
