#include <shatter/plugin/geometry/TearLines.h>

#include <shatter/plugin/common/InputError.h>
#include <shatter/plugin/geometry/Aabb.h>

#include <algorithm>
#include <sstream>

namespace shatter::geometry {

namespace {

std::string where(const ObjFile& file, int line) { return file.path + ":" + std::to_string(line); }

std::string pointText(const Eigen::Vector3d& p) {
    std::ostringstream out;
    out << "(" << p.x() << " " << p.y() << " " << p.z() << ")";
    return out.str();
}

// The visual vertices within `tolerance` of p (usually one; duplicates at a seam give more).
std::vector<int> verticesAt(const PhysicalMesh& body, const Eigen::Vector3d& p, double tolerance) {
    std::vector<int> out;
    const auto& positions = body.visual.positions;
    for (int v = 0; v < int(positions.size()); ++v)
        if ((positions[size_t(v)] - p).norm() <= tolerance) out.push_back(v);
    return out;
}

// The body's face edges as sorted vertex pairs (a < b), each once.
std::vector<std::pair<int, int>> faceEdges(const PhysicalMesh& body) {
    std::vector<std::pair<int, int>> edges;
    for (const auto& face : body.visual.faces)
        for (size_t k = 0; k < face.size(); ++k) {
            const int a = face[k], b = face[(k + 1) % face.size()];
            edges.emplace_back(std::min(a, b), std::max(a, b));
        }
    std::sort(edges.begin(), edges.end());
    edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
    return edges;
}

std::string bodyList(const PhysicalObject& object) {
    std::string out;
    for (const auto& body : object.bodies) out += (out.empty() ? "" : ", ") + body.name;
    return out;
}

} // namespace

bool isTearName(const std::string& objectName) { return objectName.rfind("tear.", 0) == 0; }

double tearPointTolerance(const PhysicalMesh& body) {
    Aabb bounds;
    for (const auto& p : body.visual.positions) bounds.extend(p);
    return std::max(1e-6, 1e-6 * bounds.diagonal());
}

void addTearLines(const ObjFile& file, const ObjObject& tear, PhysicalObject& object) {
    const std::string name = tear.name.substr(5, tear.name.find('.', 5) == std::string::npos
                                                     ? std::string::npos
                                                     : tear.name.find('.', 5) - 5);
    const std::string prefix = where(file, tear.line) + ": tear object '" + tear.name + "'";
    if (name.empty()) throw InputError(prefix + ": names no body (write tear.<body>)");
    const int index = object.findBody(name);
    if (index < 0)
        throw InputError(prefix + ": body '" + name + "' does not exist (bodies: " + bodyList(object) + ")");
    if (!tear.faces.empty())
        throw InputError(where(file, tear.faces.front().line) + ": tear object '" + tear.name +
                         "' holds a face; a tear object holds only polylines (l)");
    PhysicalMesh& body = object.bodies[size_t(index)];
    const double tolerance = tearPointTolerance(body);
    const std::vector<std::pair<int, int>> edges = faceEdges(body);
    for (const ObjPolyline& polyline : tear.polylines) {
        const std::string at = where(file, polyline.line) + ": tear line of body '" + name + "'";
        std::vector<std::vector<int>> matched;
        for (size_t k = 0; k < polyline.vertices.size(); ++k) {
            const Eigen::Vector3d& p = file.positions[size_t(polyline.vertices[k])];
            matched.push_back(verticesAt(body, p, tolerance));
            if (matched.back().empty()) {
                std::ostringstream msg;
                msg << at << ": point " << k + 1 << " " << pointText(p) << " is not a vertex of the body's mesh"
                    << " (tolerance " << tolerance << " m)";
                throw InputError(msg.str());
            }
        }
        for (size_t k = 0; k + 1 < matched.size(); ++k) {
            bool found = false;
            for (int a : matched[k])
                for (int b : matched[k + 1]) {
                    const std::pair<int, int> edge(std::min(a, b), std::max(a, b));
                    if (!std::binary_search(edges.begin(), edges.end(), edge)) continue;
                    body.tearEdges.push_back(edge);
                    found = true;
                }
            if (!found)
                throw InputError(at + ": points " + std::to_string(k + 1) + " and " + std::to_string(k + 2) +
                                 " are not joined by an edge of the body's faces");
        }
    }
    std::sort(body.tearEdges.begin(), body.tearEdges.end());
    body.tearEdges.erase(std::unique(body.tearEdges.begin(), body.tearEdges.end()), body.tearEdges.end());
}

} // namespace shatter::geometry
