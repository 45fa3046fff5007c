#include <shatter/bullet_ext/shape/ConvexHullOfPoints.h>

#include <shatter/plugin/common/InputError.h>

#include <LinearMath/btConvexHullComputer.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>

namespace shatter {

namespace {

// Bullet's IsAlmostZero (btConvexPolyhedron.cpp): no component above 1e-6.
bool almostZero(const btVector3& v) {
    return !(btFabs(v.x()) > 1e-6 || btFabs(v.y()) > 1e-6 || btFabs(v.z()) > 1e-6);
}

// Each face's plane as initializePolyhedralFeatures sets it: the normal of its first two
// edges, through its innermost vertex.
void setPlanes(btConvexPolyhedron& poly) {
    for (int f = 0; f < poly.m_faces.size(); ++f) {
        btFace& face = poly.m_faces[f];
        const btVector3& v0 = poly.m_vertices[face.m_indices[0]];
        const btVector3& v1 = poly.m_vertices[face.m_indices[1]];
        const btVector3& v2 = poly.m_vertices[face.m_indices[2]];
        btVector3 e0 = v1 - v0, e1 = v2 - v1;
        e0.normalize();
        e1.normalize();
        btVector3 n = e0.cross(e1);
        n.normalize();
        btScalar offset = 1e30f;
        for (int k = 0; k < face.m_indices.size(); ++k) offset = std::min(offset, poly.m_vertices[face.m_indices[k]].dot(n));
        face.m_plane[0] = n.x();
        face.m_plane[1] = n.y();
        face.m_plane[2] = n.z();
        face.m_plane[3] = -offset;
    }
}

// The unique edge directions in initialize()'s order: every edge of every face, from its
// higher vertex index to its lower, unless one is within 1e-6 of it either way round. Only
// known edges whose |x| is within 1e-6 of the new one's can be, so they are looked up among
// those whose |x| falls in the same slot of 4e-6 or the two next to it (a hash of slots),
// instead of all of them. Which edge matches does not matter, only whether one does, so
// looking at more candidates than needed changes nothing. (A list sorted by |x| cost 1.5 M of
// the 4.7 M this file spent on the vase's first break, 20 hulls: the insertions moved half the
// list each.) Not shared with GroupShape.cpp's addUniqueEdges and setInternalObjects, on
// purpose: those take a primitive's exact faces in double and need not match Bullet, while
// this file must give Bullet's features bit for bit.
void setUniqueEdges(btConvexPolyhedron& poly) {
    int edges = 0;
    for (int f = 0; f < poly.m_faces.size(); ++f) edges += poly.m_faces[f].m_indices.size();
    constexpr btScalar kSlotsPerUnit = 250000; // slots of 4e-6: |x| <= 1
    size_t heads = 16;
    while (heads < 2 * size_t(edges)) heads *= 2;
    std::vector<int> head(heads, -1), next; // chains of unique edge indices per hashed slot
    next.reserve(size_t(edges));
    auto chainOf = [&](int slot) -> int& { return head[(std::uint32_t(slot) * 2654435761u) & (heads - 1)]; };
    for (int f = 0; f < poly.m_faces.size(); ++f) {
        const btFace& face = poly.m_faces[f];
        const int n = face.m_indices.size();
        for (int j = 0; j < n; ++j) {
            const int a = face.m_indices[j], b = face.m_indices[(j + 1) % n];
            btVector3 edge = poly.m_vertices[std::min(a, b)] - poly.m_vertices[std::max(a, b)];
            edge.normalize();
            // A zero-length edge normalises to NaN, which may not be converted to int: it gets a
            // slot of its own (and, as in Bullet's search, matches nothing).
            const btScalar ax = btFabs(edge.x());
            const int slot = ax <= btScalar(2) ? int(ax * kSlotsPerUnit) : -2;
            bool found = false;
            for (int s = slot - 1; s <= slot + 1 && !found; ++s)
                for (int u = chainOf(s); u >= 0 && !found; u = next[size_t(u)])
                    found = almostZero(poly.m_uniqueEdges[u] - edge) || almostZero(poly.m_uniqueEdges[u] + edge);
            if (found) continue;
            int& chain = chainOf(slot);
            next.push_back(chain);
            chain = poly.m_uniqueEdges.size();
            poly.m_uniqueEdges.push_back(edge);
        }
    }
}

// initialize()'s centre (the area-weighted centroid of the faces' triangle fans), inner
// radius about it and bounding box (mC, mE: twice its centre and its size).
void setCentreAndBounds(btConvexPolyhedron& poly) {
    btScalar total = 0;
    poly.m_localCenter.setValue(0, 0, 0);
    for (int f = 0; f < poly.m_faces.size(); ++f) {
        const btFace& face = poly.m_faces[f];
        const int n = face.m_indices.size();
        const btVector3& p0 = poly.m_vertices[face.m_indices[0]];
        for (int j = 1; j <= n - 2; ++j) {
            const btVector3& p1 = poly.m_vertices[face.m_indices[j]];
            const btVector3& p2 = poly.m_vertices[face.m_indices[(j + 1) % n]];
            const btScalar area = ((p0 - p1).cross(p0 - p2)).length() * 0.5f;
            poly.m_localCenter += area * ((p0 + p1 + p2) / 3.0f);
            total += area;
        }
    }
    poly.m_localCenter /= total;
    poly.m_radius = FLT_MAX;
    for (int f = 0; f < poly.m_faces.size(); ++f) {
        const btScalar* p = poly.m_faces[f].m_plane;
        poly.m_radius = std::min(poly.m_radius, btFabs(poly.m_localCenter.dot(btVector3(p[0], p[1], p[2])) + p[3]));
    }
    btVector3 lo(FLT_MAX, FLT_MAX, FLT_MAX), hi(-FLT_MAX, -FLT_MAX, -FLT_MAX);
    for (int i = 0; i < poly.m_vertices.size(); ++i) {
        lo.setMin(poly.m_vertices[i]);
        hi.setMax(poly.m_vertices[i]);
    }
    poly.mC = hi + lo;
    poly.mE = hi - lo;
}

// The inner box Bullet's initialize() searches for, in closed form (`poly` has its faces,
// centre and inner radius): a cube in the inner sphere (half side radius/√3), stretched along
// the axis of the largest extent as far as every face allows (at most half that extent), then
// widened across it as far as every face allows (at most to the inner radius). Bullet steps
// towards the same limits in 1/1024ths. The limits are exact in double; rounded to float, a
// corner can stick out of a face by half a float step, where Bullet's search, which tests each
// step in float (testContainment), never goes. So the box then steps in until Bullet's own test
// holds, but not below Bullet's starting cube (half side `r`, in float as Bullet computes it):
// that cube can fail the float test by rounding too, and Bullet keeps it then.
void stretchInnerBox(btConvexPolyhedron& poly) {
    const btScalar r = poly.m_radius / std::sqrt(btScalar(3));
    const double cube = double(r);
    const int along = poly.mE.maxAxis();
    const int a = (along + 1) % 3, b = (along + 2) % 3;
    // Each face's room beyond the box's centre: its distance from the centre.
    auto room = [&](const btFace& face) {
        return -(double(face.m_plane[0]) * poly.m_localCenter.x() + double(face.m_plane[1]) * poly.m_localCenter.y() +
                 double(face.m_plane[2]) * poly.m_localCenter.z() + double(face.m_plane[3]));
    };
    // Stretched: each face bounds the half length along `along` with the cube's other sides.
    double length = 0.5 * double(poly.mE[along]);
    for (int f = 0; f < poly.m_faces.size(); ++f) {
        const btFace& face = poly.m_faces[f];
        const double slack = room(face) - (std::abs(face.m_plane[a]) + std::abs(face.m_plane[b])) * cube;
        if (face.m_plane[along] != 0) length = std::min(length, slack / std::abs(face.m_plane[along]));
    }
    length = std::max(length, cube);
    // Widened: both other sides grow alike, up to the inner radius.
    double side = double(poly.m_radius);
    for (int f = 0; f < poly.m_faces.size(); ++f) {
        const btFace& face = poly.m_faces[f];
        const double across = std::abs(face.m_plane[a]) + std::abs(face.m_plane[b]);
        const double slack = room(face) - std::abs(face.m_plane[along]) * length;
        if (across > 0) side = std::min(side, slack / across);
    }
    side = std::max(side, cube);
    // cube is a float, so neither rounds below it.
    poly.m_extents.setZero(); // its fourth float too (read by nothing but btVector3's ==, which a copy compared)
    poly.m_extents[along] = btScalar(length);
    poly.m_extents[a] = poly.m_extents[b] = btScalar(side);
    // In by 1, 2, 4, ... float steps of each corner's coordinate: the first step is nearly
    // always enough, and the doubling ends the loop within a few dozen steps whatever happens.
    for (btScalar steps = 1; !poly.testContainment(); steps *= 2) {
        bool moved = false;
        for (int k = 0; k < 3; ++k) {
            const btScalar corner = btFabs(poly.m_localCenter[k]) + poly.m_extents[k];
            const btScalar in = std::max(r, poly.m_extents[k] - steps * (std::nextafter(corner, FLT_MAX) - corner));
            moved = moved || in != poly.m_extents[k];
            poly.m_extents[k] = in;
        }
        if (!moved) break; // Bullet's cube
    }
}

} // namespace

void findUniqueEdges(btConvexPolyhedron& poly) {
    if (poly.m_uniqueEdges.size()) throw std::logic_error("findUniqueEdges: the polyhedron already has edges");
    setUniqueEdges(poly);
}

void convexHullOf(const std::vector<Eigen::Vector3d>& points, btConvexPolyhedron& poly) {
    if (poly.m_vertices.size() || poly.m_faces.size() || poly.m_uniqueEdges.size())
        throw std::logic_error("convexHullOf: the polyhedron to fill is not empty");
    btConvexHullComputer hull;
    if (points.size() >= 4)
        hull.compute(points.front().data(), int(sizeof(Eigen::Vector3d)), int(points.size()), 0.0, 0.0);
    if (hull.faces.size() < 4)
        throw InputError("convexHullOf: " + std::to_string(points.size()) + " points span no volume");
    poly.m_vertices = hull.vertices;
    poly.m_faces.resize(hull.faces.size());
    int edges = 0;
    for (int f = 0; f < hull.faces.size(); ++f) {
        const btConvexHullComputer::Edge* start = &hull.edges[hull.faces[f]];
        // Sized once: growing one index at a time took three allocations a face (the vase's
        // break: 1,900 faces).
        int n = 0;
        for (const btConvexHullComputer::Edge* e = start; n == 0 || e != start; e = e->getNextEdgeOfFace()) ++n;
        btAlignedObjectArray<int>& indices = poly.m_faces[f].m_indices;
        indices.resize(n);
        const btConvexHullComputer::Edge* e = start;
        for (int k = 0; k < n; ++k, e = e->getNextEdgeOfFace()) // counter-clockwise, seen from outside
            indices[k] = e->getSourceVertex();
        edges += n;
    }
    poly.m_uniqueEdges.reserve(edges / 2); // each edge is on two faces
    setPlanes(poly);
    setUniqueEdges(poly);
    setCentreAndBounds(poly);
    stretchInnerBox(poly);
}

btConvexPolyhedron convexHullOf(const std::vector<Eigen::Vector3d>& points) {
    btConvexPolyhedron poly;
    convexHullOf(points, poly);
    return poly;
}

} // namespace shatter
