#include "demos/runner/ShapeMesh.h"

#include <shatter/bullet_ext/Convert.h>
#include <shatter/plugin/common/InputError.h>

#include <BulletCollision/BroadphaseCollision/btBroadphaseProxy.h>
#include <BulletCollision/CollisionShapes/btBoxShape.h>
#include <BulletCollision/CollisionShapes/btCapsuleShape.h>
#include <BulletCollision/CollisionShapes/btCompoundShape.h>
#include <BulletCollision/CollisionShapes/btConvexHullShape.h>
#include <BulletCollision/CollisionShapes/btCylinderShape.h>
#include <BulletCollision/CollisionShapes/btSphereShape.h>
#include <LinearMath/btConvexHullComputer.h>

#include <cmath>
#include <numbers>
#include <vector>

namespace shatter::demo {

namespace {

using geometry::VisualMesh;

// Fine enough that a ball reads as round at 1280×720, coarse enough to keep frame files small.
constexpr int kSegments = 32;
constexpr int kArcSteps = 8; // per quarter circle

// Profile point of a surface of revolution about +Y: distance from the axis and height.
struct ProfilePoint {
    double radius, height;
};

// Revolves a profile (listed from top to bottom) about the shape's up axis. Points on the
// axis become single pole vertices closed by triangle fans.
VisualMesh lathe(const std::vector<ProfilePoint>& profile, int upAxis) {
    VisualMesh mesh;
    std::vector<std::vector<int>> rings;
    for (const ProfilePoint& p : profile) {
        std::vector<int> ring;
        const int count = p.radius > 0 ? kSegments : 1;
        for (int s = 0; s < count; ++s) {
            const double phi = 2 * std::numbers::pi * s / kSegments;
            // Y-up coordinates, then a cyclic permutation (a proper rotation) to the up axis.
            const double in[3] = {p.radius * std::sin(phi), p.height, p.radius * std::cos(phi)};
            Eigen::Vector3d out;
            for (int j = 0; j < 3; ++j) out[(upAxis + j + 2) % 3] = in[j];
            ring.push_back(int(mesh.positions.size()));
            mesh.positions.push_back(out);
        }
        rings.push_back(std::move(ring));
    }
    for (size_t r = 0; r + 1 < rings.size(); ++r) {
        const auto& a = rings[r];     // upper ring
        const auto& b = rings[r + 1]; // lower ring
        for (int s = 0; s < kSegments; ++s) {
            const int t = (s + 1) % kSegments;
            if (a.size() == 1 && b.size() == 1) continue;
            if (a.size() == 1) mesh.faces.push_back({a[0], b[s], b[t]});
            else if (b.size() == 1) mesh.faces.push_back({a[s], b[0], a[t]});
            else mesh.faces.push_back({a[s], b[s], b[t], a[t]});
        }
    }
    return mesh;
}

// Quarter arcs from the top pole down to the equator (centre `top`) and from the equator
// to the bottom pole (centre `bottom`): a sphere when top == bottom, a capsule otherwise.
std::vector<ProfilePoint> roundedProfile(double radius, double top, double bottom) {
    std::vector<ProfilePoint> profile;
    for (int i = 0; i <= 2 * kArcSteps; ++i) {
        const double theta = std::numbers::pi / 2 * i / kArcSteps;
        const double centre = i <= kArcSteps ? top : bottom;
        profile.push_back({i == 0 || i == 2 * kArcSteps ? 0.0 : radius * std::sin(theta), centre + radius * std::cos(theta)});
        if (i == kArcSteps && top != bottom) profile.push_back({radius, bottom});
    }
    return profile;
}

VisualMesh boxMesh(const btVector3& half) {
    VisualMesh mesh;
    for (int i = 0; i < 8; ++i)
        mesh.positions.emplace_back(i & 1 ? half.x() : -half.x(), i & 2 ? half.y() : -half.y(), i & 4 ? half.z() : -half.z());
    mesh.faces = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
    return mesh;
}

VisualMesh hullMesh(const btConvexHullShape& shape, const std::string& body) {
    std::vector<double> coords;
    const btVector3 scale = shape.getLocalScaling();
    for (int i = 0; i < shape.getNumPoints(); ++i) {
        const btVector3 p = shape.getUnscaledPoints()[i] * scale;
        coords.insert(coords.end(), {double(p.x()), double(p.y()), double(p.z())});
    }
    btConvexHullComputer hull;
    hull.compute(coords.data(), 3 * sizeof(double), shape.getNumPoints(), 0.0, 0.0);
    if (hull.faces.size() < 4) throw InputError("body '" + body + "': convex hull shape is flat or has fewer than 4 points");
    VisualMesh mesh;
    for (int i = 0; i < hull.vertices.size(); ++i) mesh.positions.push_back(toEigen(hull.vertices[i]));
    for (int f = 0; f < hull.faces.size(); ++f) {
        std::vector<int> face;
        const btConvexHullComputer::Edge* start = &hull.edges[hull.faces[f]];
        const btConvexHullComputer::Edge* e = start;
        do {
            face.push_back(e->getSourceVertex());
            e = e->getNextEdgeOfFace();
        } while (e != start);
        mesh.faces.push_back(std::move(face));
    }
    return mesh;
}

void append(VisualMesh& into, const VisualMesh& part, const btTransform& transform) {
    const int offset = int(into.positions.size());
    const VisualMesh moved = transformed(part, transform);
    into.positions.insert(into.positions.end(), moved.positions.begin(), moved.positions.end());
    for (auto face : moved.faces) {
        for (int& v : face) v += offset;
        into.faces.push_back(std::move(face));
    }
}

} // namespace

ShapeMesh tessellate(const btCollisionShape& shape, const std::string& body) {
    switch (shape.getShapeType()) {
    case BOX_SHAPE_PROXYTYPE:
        return {boxMesh(static_cast<const btBoxShape&>(shape).getHalfExtentsWithMargin()), false};
    case SPHERE_SHAPE_PROXYTYPE: {
        const double r = static_cast<const btSphereShape&>(shape).getRadius();
        return {lathe(roundedProfile(r, 0, 0), 1), true};
    }
    case CAPSULE_SHAPE_PROXYTYPE: {
        const auto& capsule = static_cast<const btCapsuleShape&>(shape);
        const double h = capsule.getHalfHeight();
        return {lathe(roundedProfile(capsule.getRadius(), h, -h), capsule.getUpAxis()), true};
    }
    case CYLINDER_SHAPE_PROXYTYPE: {
        const auto& cylinder = static_cast<const btCylinderShape&>(shape);
        const int up = cylinder.getUpAxis();
        const double r = cylinder.getRadius(), h = cylinder.getHalfExtentsWithMargin()[up];
        return {lathe({{0, h}, {r, h}, {r, -h}, {0, -h}}, up), true};
    }
    case CONVEX_HULL_SHAPE_PROXYTYPE:
        return {hullMesh(static_cast<const btConvexHullShape&>(shape), body), false};
    case COMPOUND_SHAPE_PROXYTYPE: {
        const auto& compound = static_cast<const btCompoundShape&>(shape);
        ShapeMesh result{{}, true};
        for (int i = 0; i < compound.getNumChildShapes(); ++i) {
            const ShapeMesh child = tessellate(*compound.getChildShape(i), body);
            append(result.mesh, child.mesh, compound.getChildTransform(i));
            result.round = result.round && child.round;
        }
        return result;
    }
    default:
        throw InputError("body '" + body + "': cannot draw a " + shape.getName() +
                         " (supported: box, sphere, capsule, cylinder, convex hull, compound)");
    }
}

geometry::VisualMesh transformed(const geometry::VisualMesh& mesh, const btTransform& transform) {
    const Eigen::Isometry3d t = toEigen(transform);
    VisualMesh out;
    out.positions.reserve(mesh.positions.size());
    for (const auto& p : mesh.positions) out.positions.push_back(t * p);
    out.faces = mesh.faces;
    return out;
}

} // namespace shatter::demo
