#include <shatter/plugin/lattice/CleavingPlane.h>

#include <shatter/plugin/common/SettingCheck.h>

#include <algorithm>
#include <cmath>

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

std::vector<int> applyCleavingPlanes(Lattice& lattice, const std::vector<CleavingPlane>& planes) {
    std::vector<int> counts;
    for (const CleavingPlane& plane : planes) {
        int count = 0;
        for (int k = 0; k < lattice.linkCount(); ++k)
            if (faceNearPlane(lattice, lattice.links()[k], plane)) {
                lattice.scaleStrength(k, plane.factor);
                ++count;
            }
        counts.push_back(count);
    }
    return counts;
}

void CleavingPlane::check(const std::string& body, int index) const {
    const std::string plane = "cleaving plane " + std::to_string(index) + " ";
    requireSetting(point.allFinite(), body, plane + "point", "finite", point.norm());
    requireSetting(normal.allFinite() && normal.norm() > 0.0, body, plane + "normal", "finite and non-zero", normal.norm());
    requireNonNegative(body, plane + "distance", distance);
    requirePositive(body, plane + "factor", factor);
}

} // namespace shatter::lattice
