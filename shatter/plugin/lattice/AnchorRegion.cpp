#include <shatter/plugin/lattice/AnchorRegion.h>

#include <shatter/plugin/common/InputError.h>

#include <cmath>
#include <sstream>

namespace shatter::lattice {

AnchorRegion AnchorRegion::halfSpace(const Eigen::Vector3d& normal, double offset) {
    if (!(normal.allFinite() && normal.norm() > 0.0 && std::isfinite(offset)))
        throw InputError("an anchor half-space needs a finite non-zero normal and a finite offset");
    AnchorRegion r;
    r.kind = Kind::HalfSpace;
    r.normal = normal.normalized();
    r.offset = offset;
    return r;
}

AnchorRegion AnchorRegion::box(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
    if (!(lo.allFinite() && hi.allFinite() && (lo.array() <= hi.array()).all()))
        throw InputError("an anchor box needs finite corners with the first below the second on every axis");
    AnchorRegion r;
    r.kind = Kind::Box;
    r.lo = lo;
    r.hi = hi;
    return r;
}

bool AnchorRegion::contains(const Eigen::Vector3d& p) const {
    if (kind == Kind::HalfSpace) return normal.dot(p) <= offset;
    return (p.array() >= lo.array()).all() && (p.array() <= hi.array()).all();
}

std::string AnchorRegion::describe() const {
    std::ostringstream s;
    const auto v = [&s](const Eigen::Vector3d& x) { s << "(" << x.x() << ", " << x.y() << ", " << x.z() << ")"; };
    if (kind == Kind::HalfSpace) {
        s << "n·x <= " << offset << " with n = ";
        v(normal);
    } else {
        s << "box ";
        v(lo);
        s << "-";
        v(hi);
    }
    return s.str();
}

std::vector<int> tetsInRegion(const TetMesh& mesh, const AnchorRegion& region, const Eigen::Isometry3d& meshToWorld) {
    const bool world = region.frame == AnchorRegion::Frame::World;
    std::vector<int> out;
    for (int t = 0; t < int(mesh.tets.size()); ++t) {
        const Eigen::Vector3d c = centroid(mesh, mesh.tets[t]);
        if (region.contains(world ? Eigen::Vector3d(meshToWorld * c) : c)) out.push_back(t);
    }
    return out;
}

std::vector<int> anchoredTets(const TetMesh& mesh, const AnchorRegion& region, const std::string& body,
                              const Eigen::Isometry3d& meshToWorld) {
    std::vector<int> tets = tetsInRegion(mesh, region, meshToWorld);
    const char* frame = region.frame == AnchorRegion::Frame::World ? "world" : "mesh";
    if (tets.empty())
        throw InputError("body '" + body + "': the anchor region " + region.describe() + " (" + frame + " coordinates) holds no tet");
    return tets;
}

} // namespace shatter::lattice
