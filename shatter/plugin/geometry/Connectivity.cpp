#include <shatter/plugin/geometry/Connectivity.h>

#include <shatter/plugin/geometry/AabbTree.h>
#include <shatter/plugin/geometry/UnionFind.h>

#include <algorithm>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#include <ccd/ccd.h>

namespace shatter::geometry {

namespace {

// A primitive as libccd sees it. libccd compares against absolute epsilons, so each pair
// is moved to a common origin near both shapes and scaled to unit size.
struct ScaledShape {
    const ConvexPolyhedron* shape;
    Eigen::Vector3d origin;
    double scale;
    double radius; // sphere added to the shape, in scaled units
};

void scaledSupport(const void* object, const ccd_vec3_t* dir, ccd_vec3_t* out) {
    const auto& s = *static_cast<const ScaledShape*>(object);
    const Eigen::Vector3d d(dir->v[0], dir->v[1], dir->v[2]);
    Eigen::Vector3d p = (s.shape->support(d) - s.origin) * s.scale;
    const double length = d.norm();
    if (length > 0.0) p += (s.radius / length) * d;
    out->v[0] = p.x();
    out->v[1] = p.y();
    out->v[2] = p.z();
}

void scaledCenter(const void* object, ccd_vec3_t* out) {
    const auto& s = *static_cast<const ScaledShape*>(object);
    const Eigen::Vector3d c = (s.shape->bounds().center() - s.origin) * s.scale;
    out->v[0] = c.x();
    out->v[1] = c.y();
    out->v[2] = c.z();
}

// Start GJK along the line between the box centres: usually the separating direction.
void firstDirection(const void* a, const void* b, ccd_vec3_t* out) {
    ccd_vec3_t ca, cb;
    scaledCenter(a, &ca);
    scaledCenter(b, &cb);
    for (int i = 0; i < 3; ++i) out->v[i] = cb.v[i] - ca.v[i];
    if (out->v[0] == 0.0 && out->v[1] == 0.0 && out->v[2] == 0.0) out->v[0] = 1.0;
}

} // namespace

bool withinTolerance(const ConvexPolyhedron& a, const ConvexPolyhedron& b, double tolerance) {
    Aabb both = a.bounds();
    both.extend(b.bounds());
    const double size = std::max(both.diagonal(), tolerance);
    if (!(size > 0.0)) return true; // two points at the same place
    const double scale = 1.0 / size;
    const Eigen::Vector3d origin = both.center();
    const ScaledShape sa{&a, origin, scale, 0.5 * tolerance * scale};
    const ScaledShape sb{&b, origin, scale, 0.5 * tolerance * scale};
    ccd_t ccd;
    CCD_INIT(&ccd);
    ccd.first_dir = firstDirection;
    ccd.support1 = scaledSupport;
    ccd.support2 = scaledSupport;
    ccd.center1 = scaledCenter;
    ccd.center2 = scaledCenter;
    // Polytopes converge in a few dozen steps; the cap only guards against cycling on a
    // contact that is exactly at the tolerance, which then counts as apart.
    ccd.max_iterations = 200;
    return ccdGJKIntersect(&sa, &sb, &ccd) != 0;
}

std::vector<std::pair<int, int>> touchingPairs(const std::vector<ConvexPolyhedron>& primitives, double tolerance) {
    std::vector<Aabb> boxes;
    boxes.reserve(primitives.size());
    for (const auto& p : primitives) boxes.push_back(p.bounds().inflated(0.5 * tolerance));
    std::vector<std::pair<int, int>> candidates;
    AabbTree(boxes).selfPairs([&](int a, int b) { candidates.emplace_back(a, b); });
    std::sort(candidates.begin(), candidates.end());
    std::vector<std::pair<int, int>> pairs;
    for (const auto& [a, b] : candidates)
        if (withinTolerance(primitives[a], primitives[b], tolerance)) pairs.emplace_back(a, b);
    return pairs;
}

std::vector<int> primitivesTouching(const std::vector<ConvexPolyhedron>& primitives, const ConvexPolyhedron& probe,
                                    double tolerance) {
    const Aabb reach = probe.bounds().inflated(tolerance);
    std::vector<int> out;
    for (size_t i = 0; i < primitives.size(); ++i)
        if (primitives[i].bounds().overlaps(reach) && withinTolerance(primitives[i], probe, tolerance))
            out.push_back(int(i));
    return out;
}

int countComponents(int nodeCount, const std::vector<std::pair<int, int>>& edges) {
    UnionFind sets(nodeCount);
    int components = nodeCount;
    for (const auto& [a, b] : edges)
        if (sets.unite(a, b)) --components;
    return components;
}

// Whether the id lists a and b have an id in common (pieces that share a vertex id touch;
// fracture's island test). Each of a's ids against all of b's with one branch, four at a time
// (SSE2; by std::find fracture's joining took 0.6 M instructions more of 8.2 M in five events
// of the 16k shell); the last four overlap the others rather than a scalar tail (with a
// branch per four and a scalar tail, five events took 0.13 M instructions more).
bool shareAnId(const std::vector<int>& a, const std::vector<int>& b) {
    const int* const other = b.data();
    const size_t n = b.size();
#if defined(__SSE2__)
    if (n >= 4) {
        auto four = [other](size_t k) { return _mm_loadu_si128(reinterpret_cast<const __m128i*>(other + k)); };
        const __m128i last = four(n - 4);
        for (const int i : a) {
            const __m128i id = _mm_set1_epi32(i);
            __m128i hits = _mm_cmpeq_epi32(id, last);
            for (size_t k = 0; k + 4 < n; k += 4) hits = _mm_or_si128(hits, _mm_cmpeq_epi32(id, four(k)));
            if (_mm_movemask_epi8(hits) != 0) return true;
        }
        return false;
    }
#endif
    for (const int i : a)
        for (size_t k = 0; k < n; ++k)
            if (other[k] == i) return true;
    return false;
}

} // namespace shatter::geometry
