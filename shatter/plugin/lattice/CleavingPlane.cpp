#include <shatter/plugin/lattice/CleavingPlane.h>

#include <shatter/plugin/common/InputError.h>

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

void validateCleavingPlanes(const std::vector<CleavingPlane>& planes, const std::string& body) {
    for (size_t i = 0; i < planes.size(); ++i) {
        const CleavingPlane& p = planes[i];
        const std::string what = body + ": cleaving plane " + std::to_string(i) + ": ";
        if (!p.point.allFinite()) throw InputError(what + "point is not finite");
        if (!p.normal.allFinite() || p.normal.norm() == 0.0) throw InputError(what + "normal must be finite and non-zero");
        if (!(p.distance >= 0.0 && std::isfinite(p.distance))) throw InputError(what + "distance must be >= 0 m and finite");
        if (!(p.factor > 0.0 && std::isfinite(p.factor))) throw InputError(what + "factor must be > 0 and finite");
    }
}

} // namespace shatter::lattice
