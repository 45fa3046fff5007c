#include <shatter/plugin/geometry/ClosedConvexParts.h>

#include <shatter/plugin/geometry/ClosedSurface.h>
#include <shatter/plugin/geometry/Polygon.h>
#include <shatter/plugin/geometry/UnionFind.h>

#include <algorithm>
#include <map>
#include <numeric>

namespace shatter::geometry {

namespace {

// Faces grouped by connection through shared (welded) vertices, in order of first face.
std::vector<std::vector<int>> connectedFaceGroups(const std::vector<std::vector<int>>& faces,
                                                  const std::vector<int>& rep) {
    UnionFind sets(int(faces.size()));
    std::vector<int> firstFace(rep.size(), -1);
    for (size_t f = 0; f < faces.size(); ++f)
        for (int v : faces[f]) {
            int& first = firstFace[rep[v]];
            if (first < 0) first = int(f);
            else sets.unite(first, int(f));
        }
    std::map<int, std::vector<int>> groups; // keyed by root = smallest face index
    for (size_t f = 0; f < faces.size(); ++f) groups[sets.find(int(f))].push_back(int(f));
    std::vector<std::vector<int>> out;
    for (auto& [root, members] : groups) out.push_back(std::move(members));
    return out;
}

// One part as a standalone polyhedron: welded vertices, faces over them, extra
// coincident vertices appended after the face vertices.
struct PartMesh {
    std::vector<Eigen::Vector3d> vertices;
    std::vector<std::vector<int>> faces;
    std::vector<int> ids;
    size_t faceVertexCount = 0;
};

PartMesh partMesh(const std::vector<Eigen::Vector3d>& points, const std::vector<std::vector<int>>& faces,
                  const std::vector<int>& part, const std::vector<int>& rep) {
    std::vector<int> used;
    for (int f : part) used.insert(used.end(), faces[f].begin(), faces[f].end());
    std::sort(used.begin(), used.end());
    used.erase(std::unique(used.begin(), used.end()), used.end());
    PartMesh mesh;
    std::map<int, int> local; // representative point → local vertex
    for (int v : used)
        if (!local.count(rep[v])) {
            // The first of a coincident group (ascending index) stands for all of them.
            local[rep[v]] = int(mesh.vertices.size());
            mesh.vertices.push_back(points[v]);
            mesh.ids.push_back(v);
        }
    mesh.faceVertexCount = mesh.vertices.size();
    for (int v : used)
        if (mesh.ids[local[rep[v]]] != v) {
            mesh.vertices.push_back(points[v]);
            mesh.ids.push_back(v);
        }
    for (int f : part) {
        std::vector<int> polygon;
        for (int v : faces[f]) polygon.push_back(local[rep[v]]);
        mesh.faces.push_back(std::move(polygon));
    }
    return mesh;
}

Plane facePlane(const std::vector<Eigen::Vector3d>& vertices, const std::vector<int>& face) {
    const Eigen::Vector3d n = polygonAreaVector(vertices, face).normalized();
    double d = 0.0;
    for (int i : face) d += n.dot(vertices[i]);
    return {n, d / double(face.size())};
}

bool behind(const Plane& plane, const std::vector<Eigen::Vector3d>& vertices, const std::vector<int>& which,
            double tolerance) {
    for (int i : which)
        if (!(plane.signedDistance(vertices[i]) <= tolerance)) return false;
    return true;
}

// Convex at every edge first (cheap, rejects most non-convex parts), then the full test.
bool isConvex(const PartMesh& mesh, double tolerance) {
    std::vector<Plane> planes;
    for (const auto& face : mesh.faces) {
        if (!(polygonAreaVector(mesh.vertices, face).norm() > 0.0)) return false;
        planes.push_back(facePlane(mesh.vertices, face));
    }
    std::map<std::pair<int, int>, int> faceOfEdge;
    for (size_t f = 0; f < mesh.faces.size(); ++f)
        for (size_t k = 0; k < mesh.faces[f].size(); ++k)
            faceOfEdge[{mesh.faces[f][k], mesh.faces[f][(k + 1) % mesh.faces[f].size()]}] = int(f);
    for (size_t f = 0; f < mesh.faces.size(); ++f) {
        if (!behind(planes[f], mesh.vertices, mesh.faces[f], tolerance)) return false; // face not planar
        for (size_t k = 0; k < mesh.faces[f].size(); ++k) {
            const int a = mesh.faces[f][k], b = mesh.faces[f][(k + 1) % mesh.faces[f].size()];
            if (!behind(planes[f], mesh.vertices, mesh.faces[faceOfEdge.at({b, a})], tolerance)) return false;
        }
    }
    std::vector<int> all(mesh.faceVertexCount);
    std::iota(all.begin(), all.end(), 0);
    for (const auto& plane : planes)
        if (!behind(plane, mesh.vertices, all, tolerance)) return false;
    return true;
}

} // namespace

std::vector<ClosedConvexPart> findClosedConvexParts(const std::vector<Eigen::Vector3d>& points,
                                                    const std::vector<std::vector<int>>& faces,
                                                    double convexityTolerance) {
    const std::vector<int> rep = coincidentRepresentatives(points);
    std::vector<ClosedConvexPart> parts;
    for (auto& group : connectedFaceGroups(faces, rep)) {
        PartMesh mesh = partMesh(points, faces, group, rep);
        if (!isClosedSurface(mesh.faces)) continue;
        const double volume = polyhedronMassProperties(mesh.vertices, mesh.faces, 1.0).volume;
        if (!(volume != 0.0)) continue;
        const bool flipped = volume < 0.0;
        if (flipped)
            for (auto& face : mesh.faces) std::reverse(face.begin(), face.end());
        if (!isConvex(mesh, convexityTolerance)) continue;
        try {
            ConvexPolyhedron primitive =
                ConvexPolyhedron::create(std::move(mesh.vertices), std::move(mesh.faces), std::move(mesh.ids));
            parts.push_back({std::move(group), flipped, std::move(primitive)});
        } catch (const InputError&) {
            // Convex within the body's tolerance but not within the part's own (a small
            // part of a large body): its faces are extruded instead.
        }
    }
    return parts;
}

} // namespace shatter::geometry
