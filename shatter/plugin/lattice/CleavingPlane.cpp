#include <shatter/plugin/lattice/CleavingPlane.h>

#include <shatter/plugin/common/SettingCheck.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>

namespace shatter::lattice {

bool faceNearPlane(const Lattice& lattice, const Link& link, const CleavingPlane& plane) {
    const Eigen::Vector3d n = plane.normal.normalized();
    double lo = INFINITY, hi = -INFINITY;
    for (int v : link.face) {
        const double d = n.dot(lattice.mesh().nodes[v] - plane.point);
        lo = std::min(lo, d);
        hi = std::max(hi, d);
    }
    // Cut through its interior, or its centre within the distance (a face lying in the plane).
    // A face that only touches the plane at a corner or an edge is not on it.
    return (lo < 0.0 && hi > 0.0) || std::abs(n.dot(link.faceCentre - plane.point)) <= plane.distance;
}

namespace {

// The link joins tets whose centroids lie on the plane's two sides. A crack runs only through
// these: they part the body into the tets on either side, where breaking every link near the
// plane would also free, as loose single tets, the tets the plane cuts through.
bool separates(const Lattice& lattice, const Link& link, const CleavingPlane& plane) {
    const Eigen::Vector3d n = plane.normal.normalized();
    const double a = n.dot(lattice.particles()[link.a].position - plane.point);
    const double b = n.dot(lattice.particles()[link.b].position - plane.point);
    return (a < 0.0) != (b < 0.0);
}

} // namespace

std::vector<int> applyCleavingPlanes(Lattice& lattice, const std::vector<CleavingPlane>& planes) {
    std::vector<int> counts;
    for (const CleavingPlane& plane : planes) {
        int count = 0;
        for (int k = 0; k < lattice.linkCount(); ++k)
            if (faceNearPlane(lattice, lattice.links()[k], plane)) {
                lattice.scaleStrength(k, plane.factor);
                if (plane.crackRuns && separates(lattice, lattice.links()[k], plane)) lattice.setCrackRuns(k);
                ++count;
            }
        counts.push_back(count);
    }
    return counts;
}

void runCracks(Lattice& lattice, std::vector<int>& broken, size_t from) {
    std::vector<int> front;
    for (size_t i = from; i < broken.size(); ++i)
        if (lattice.links()[broken[i]].crackRuns) front.push_back(broken[i]);
    if (front.empty()) return;
    // The crack runs from face to face of the plane across their shared edges (two tets
    // beside the plane rarely share one: a face of a split cube is two tets' faces).
    std::map<std::pair<int, int>, std::vector<int>> byEdge;
    auto edges = [](const Link& l) {
        std::array<std::pair<int, int>, 3> e;
        for (int i = 0; i < 3; ++i) e[i] = std::minmax(l.face[i], l.face[(i + 1) % 3]);
        return e;
    };
    for (int k = 0; k < lattice.linkCount(); ++k)
        if (lattice.links()[k].crackRuns)
            for (const auto& e : edges(lattice.links()[k])) byEdge[e].push_back(k);
    while (!front.empty()) {
        const Link& l = lattice.links()[front.back()];
        front.pop_back();
        for (const auto& e : edges(l))
            for (int k : byEdge[e]) {
                const Link& next = lattice.links()[k];
                if (next.broken || !std::isfinite(next.strength)) continue;
                lattice.breakLink(k);
                broken.push_back(k);
                front.push_back(k);
            }
    }
}

void CleavingPlane::check(const std::string& body, int index) const {
    const std::string plane = "cleaving plane " + std::to_string(index) + " ";
    requireSetting(point.allFinite(), body, plane + "point", "finite", point.norm());
    requireSetting(normal.allFinite() && normal.norm() > 0.0, body, plane + "normal", "finite and non-zero", normal.norm());
    requireNonNegative(body, plane + "distance", distance);
    requirePositive(body, plane + "factor", factor);
}

} // namespace shatter::lattice
