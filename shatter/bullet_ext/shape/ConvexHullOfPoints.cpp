#include <shatter/bullet_ext/shape/ConvexHullOfPoints.h>

#include <shatter/plugin/common/InputError.h>

#include <LinearMath/btConvexHullComputer.h>

#include <algorithm>
#include <string>

namespace shatter {

namespace {

using Edge = btConvexHullComputer::Edge;

// The vertices of `group` (indices into `points`) that bound their convex hull in the plane
// normal to `normal`, counter-clockwise seen from the side `normal` points to (Andrew's
// monotone chain; points on a side between two corners are left out).
std::vector<int> hullInPlane(const std::vector<Eigen::Vector3d>& points, std::vector<int> group,
                             const Eigen::Vector3d& normal) {
    const Eigen::Vector3d u = normal.unitOrthogonal(), v = normal.cross(u);
    auto at = [&](int i) { return Eigen::Vector2d(u.dot(points[size_t(i)]), v.dot(points[size_t(i)])); };
    std::sort(group.begin(), group.end(), [&](int a, int b) {
        const Eigen::Vector2d pa = at(a), pb = at(b);
        return pa.x() < pb.x() || (pa.x() == pb.x() && pa.y() < pb.y());
    });
    auto turnsLeft = [&](int o, int a, int b) {
        const Eigen::Vector2d oa = at(a) - at(o), ob = at(b) - at(o);
        return oa.x() * ob.y() - oa.y() * ob.x() > 0.0;
    };
    std::vector<int> loop(2 * group.size());
    size_t k = 0;
    for (size_t i = 0; i < group.size(); ++i) { // lower chain
        while (k >= 2 && !turnsLeft(loop[k - 2], loop[k - 1], group[i])) --k;
        loop[k++] = group[i];
    }
    for (size_t i = group.size() - 1, lower = k + 1; i-- > 0;) { // upper chain
        while (k >= lower && !turnsLeft(loop[k - 2], loop[k - 1], group[i])) --k;
        loop[k++] = group[i];
    }
    loop.resize(k - 1); // the last is the first again
    return loop;
}

} // namespace

geometry::ConvexPolyhedron convexHullOf(const std::vector<Eigen::Vector3d>& points) {
    btConvexHullComputer hull;
    if (points.size() >= 4)
        hull.compute(points.front().data(), int(sizeof(Eigen::Vector3d)), int(points.size()), 0.0, 0.0);
    if (hull.faces.size() < 4)
        throw InputError("convexHullOf: " + std::to_string(points.size()) + " points span no volume");
    // The computer's vertices are its grid's; the hull's are the input points they came from.
    std::vector<Eigen::Vector3d> vertices(size_t(hull.vertices.size()));
    std::vector<int> ids(vertices.size());
    for (size_t i = 0; i < vertices.size(); ++i) {
        ids[i] = hull.original_vertex_index[int(i)];
        vertices[i] = points[size_t(ids[i])];
    }
    // Each computer face's vertex loop (counter-clockwise from outside), its Newell normal
    // (length twice its area), and the face of every edge.
    const int faceCount = hull.faces.size();
    const Edge* first = &hull.edges[0];
    std::vector<std::vector<int>> loops(static_cast<size_t>(faceCount));
    std::vector<Eigen::Vector3d> normals(static_cast<size_t>(faceCount));
    std::vector<int> faceOfEdge(size_t(hull.edges.size()), -1);
    for (int f = 0; f < faceCount; ++f) {
        const Edge* start = &hull.edges[hull.faces[f]];
        const Edge* e = start;
        do {
            faceOfEdge[size_t(e - first)] = f;
            loops[size_t(f)].push_back(e->getSourceVertex());
            e = e->getNextEdgeOfFace();
        } while (e != start);
        normals[size_t(f)] = geometry::newellNormal(vertices, loops[size_t(f)]);
    }
    // Faces whose normals lie within the weld threshold of a first one, reached from it across
    // shared edges, become one face: the hull in their plane of all their vertices.
    std::vector<char> taken(static_cast<size_t>(faceCount), 0);
    std::vector<std::vector<int>> faces;
    std::vector<int> group, members;
    for (int f = 0; f < faceCount; ++f) {
        if (taken[size_t(f)]) continue;
        taken[size_t(f)] = 1;
        const Eigen::Vector3d reference = normals[size_t(f)].normalized();
        Eigen::Vector3d normal = Eigen::Vector3d::Zero();
        group.assign(1, f);
        for (size_t g = 0; g < group.size(); ++g) {
            normal += normals[size_t(group[g])];
            const Edge* start = &hull.edges[hull.faces[group[g]]];
            const Edge* e = start;
            do {
                const int next = faceOfEdge[size_t(e->getReverseEdge() - first)];
                if (!taken[size_t(next)] && normals[size_t(next)].normalized().dot(reference) > kFaceWeldCosine) {
                    taken[size_t(next)] = 1;
                    group.push_back(next);
                }
                e = e->getNextEdgeOfFace();
            } while (e != start);
        }
        if (group.size() == 1) {
            faces.push_back(std::move(loops[size_t(f)]));
            continue;
        }
        members.clear();
        for (int g : group) members.insert(members.end(), loops[size_t(g)].begin(), loops[size_t(g)].end());
        std::sort(members.begin(), members.end());
        members.erase(std::unique(members.begin(), members.end()), members.end());
        faces.push_back(hullInPlane(vertices, members, normal.normalized()));
    }
    return geometry::ConvexPolyhedron::createTrusted(std::move(vertices), std::move(faces), std::move(ids));
}

} // namespace shatter
