#include <shatter/plugin/fracture/FracturePattern.h>

#include <shatter/plugin/common/SettingCheck.h>
#include <shatter/plugin/geometry/UnionFind.h>

#include <algorithm>
#include <cmath>

namespace shatter::fracture {

namespace {

// Index of every face plane in a flat list over all cells.
struct FlatFaces {
    std::vector<int> first; // per cell: index of its first face (+ total)
    explicit FlatFaces(const std::vector<geometry::ConvexPolyhedron>& cells) {
        first.push_back(0);
        for (const auto& c : cells) first.push_back(first.back() + int(c.planes().size()));
    }
};

bool samePlane(const geometry::Plane& a, const geometry::Plane& b, double sign, double tolerance) {
    return (a.normal - sign * b.normal).norm() <= tolerance && std::abs(a.offset - sign * b.offset) <= tolerance;
}

} // namespace

void finishPattern(FracturePattern& pattern, double tolerance) {
    const auto& cells = pattern.cells;
    if (pattern.centres.empty())
        for (const auto& c : cells) pattern.centres.push_back(c.massProperties(1.0).centerOfMass);

    // Only cells whose boxes touch can share a face; the pattern is built once, so the
    // pairwise box test over cells (not over primitives) is cheap enough.
    const FlatFaces flat(cells);
    geometry::UnionFind sets(flat.first.back());
    for (size_t i = 0; i < cells.size(); ++i)
        for (size_t j = i + 1; j < cells.size(); ++j) {
            if (!cells[i].bounds().inflated(tolerance).overlaps(cells[j].bounds())) continue;
            const auto& pi = cells[i].planes();
            const auto& pj = cells[j].planes();
            for (size_t a = 0; a < pi.size(); ++a)
                for (size_t b = 0; b < pj.size(); ++b)
                    if (samePlane(pi[a], pj[b], -1.0, tolerance) || samePlane(pi[a], pj[b], 1.0, tolerance))
                        sets.unite(flat.first[i] + int(a), flat.first[j] + int(b));
        }

    pattern.planes.clear();
    pattern.cellFaces.assign(cells.size(), {});
    std::vector<int> planeOfRoot(size_t(flat.first.back()), -1);
    std::vector<const geometry::Plane*> flatPlane;
    for (const auto& c : cells)
        for (const auto& p : c.planes()) flatPlane.push_back(&p);
    for (size_t i = 0; i < cells.size(); ++i)
        for (size_t a = 0; a < cells[i].planes().size(); ++a) {
            const int f = flat.first[i] + int(a);
            const int root = sets.find(f);
            if (planeOfRoot[root] < 0) { // roots are the smallest index of their set: seen first
                planeOfRoot[root] = int(pattern.planes.size());
                pattern.planes.push_back(*flatPlane[f]);
            }
            const int k = planeOfRoot[root];
            const double sign = pattern.planes[k].normal.dot(flatPlane[f]->normal) >= 0.0 ? 1.0 : -1.0;
            pattern.cellFaces[i].push_back({k, sign});
        }
    pattern.domain.clear(); // on the old planes; a pattern that knows its domain sets it again
}

void setBoxDomain(FracturePattern& pattern, const geometry::Aabb& box, double tolerance) {
    pattern.domain.clear();
    for (int axis = 0; axis < 3; ++axis)
        for (const double side : {-1.0, 1.0}) {
            geometry::Plane wall;
            wall.normal = side * Eigen::Vector3d::Unit(axis);
            wall.offset = side * (side < 0 ? box.min[axis] : box.max[axis]);
            const auto it = std::find_if(pattern.planes.begin(), pattern.planes.end(), [&](const geometry::Plane& p) {
                return samePlane(p, wall, 1.0, tolerance) || samePlane(p, wall, -1.0, tolerance);
            });
            if (it == pattern.planes.end()) { // no cell reaches this wall: the cells do not fill the box
                pattern.domain.clear();
                return;
            }
            const double sign = it->normal.dot(wall.normal) >= 0.0 ? 1.0 : -1.0;
            pattern.domain.push_back({int(it - pattern.planes.begin()), sign});
        }
}

void checkPattern(const FracturePattern& pattern, const std::string& what) {
    if (pattern.cells.empty()) throw InputError(what + ": the fracture pattern has no cells");
    requirePositive(what, "pattern radius", pattern.radius);
    if (pattern.centres.size() != pattern.cells.size() || pattern.cellFaces.size() != pattern.cells.size())
        throw InputError(what + ": the fracture pattern has " + std::to_string(pattern.cells.size()) +
                         " cells but derived data for " + std::to_string(pattern.cellFaces.size()) +
                         " (call finishPattern after editing cells)");
}

void VoronoiPatternSettings::check(const std::string& what) const {
    requireAtLeast(what, "Voronoi pattern cells", cells, 1);
    requirePositive(what, "Voronoi pattern radius", radius);
    requireNonNegative(what, "Voronoi pattern site radius", siteRadius);
    requireNonNegative(what, "Voronoi pattern bias exponent", biasExponent);
}

void GlassPatternSettings::check(const std::string& what) const {
    requireAtLeast(what, "glass pattern sectors", sectors, 3);
    requireAtLeast(what, "glass pattern rings", rings, 1);
    requirePositive(what, "glass pattern first ring", firstRing);
    requireSetting(std::isfinite(growth) && growth > 1.0, what, "glass pattern growth", "> 1 and finite", growth);
    requireWithin(what, "glass pattern jitter", jitter, 0.0, 0.45);
    requireNonNegative(what, "glass pattern radius", radius);
}

void GridPatternSettings::check(const std::string& what) const {
    requireAtLeast(what, "grid pattern count", count, 1);
    requirePositive(what, "grid pattern cell size", cellSize);
    requireWithin(what, "grid pattern jitter", jitter, 0.0, 0.45);
    requireNonNegative(what, "grid pattern radius", radius);
}

} // namespace shatter::fracture
