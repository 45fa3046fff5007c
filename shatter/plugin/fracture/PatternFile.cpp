#include <shatter/plugin/fracture/FracturePattern.h>

#include <shatter/plugin/common/InputError.h>
#include <shatter/plugin/geometry/ObjFile.h>

#include <algorithm>
#include <array>
#include <map>

namespace shatter::fracture {

namespace {

// The object's faces over its own vertices; vertices at identical coordinates are one
// vertex, so a cell written without shared indices is still closed.
geometry::ConvexPolyhedron cellOfObject(const geometry::ObjFile& file, const geometry::ObjObject& object) {
    std::map<std::array<double, 3>, int> local;
    std::vector<Eigen::Vector3d> vertices;
    std::vector<std::vector<int>> faces;
    for (const auto& face : object.faces) {
        std::vector<int> polygon;
        for (int v : face.vertices) {
            const Eigen::Vector3d& p = file.positions[size_t(v)];
            auto [it, added] = local.try_emplace({p.x(), p.y(), p.z()}, int(vertices.size()));
            if (added) vertices.push_back(p);
            polygon.push_back(it->second);
        }
        faces.push_back(std::move(polygon));
    }
    std::vector<int> ids(vertices.size());
    for (size_t i = 0; i < ids.size(); ++i) ids[i] = int(i);
    const std::string what = file.path + ": cell '" + object.name + "' (line " + std::to_string(object.line) + ")";
    return geometry::ConvexPolyhedron::create(std::move(vertices), std::move(faces), std::move(ids), what);
}

} // namespace

FracturePattern loadPattern(const std::string& objPath) { return patternFromObj(geometry::loadObj(objPath)); }

FracturePattern patternFromObj(const geometry::ObjFile& file) {
    FracturePattern pattern;
    for (const auto& object : file.objects) pattern.cells.push_back(cellOfObject(file, object));
    if (pattern.cells.empty()) throw InputError(file.path + ": the fracture pattern has no cells");
    finishPattern(pattern);
    for (const auto& c : pattern.centres) pattern.radius = std::max(pattern.radius, c.norm());
    pattern.radius = pattern.radius * (1.0 + 1e-9) + 1e-12; // every cell breaks free
    return pattern;
}

} // namespace shatter::fracture
