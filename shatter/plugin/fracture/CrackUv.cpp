#include <shatter/plugin/fracture/CrackUv.h>

#include <shatter/plugin/geometry/ConvexPolyhedron.h>

namespace shatter::fracture {

std::vector<Eigen::Vector2d> crackFaceUvs(const std::vector<Eigen::Vector3d>& positions, const std::vector<int>& face) {
    Eigen::Vector3d n = geometry::newellNormal(positions, face);
    int largest = 0;
    n.cwiseAbs().maxCoeff(&largest);
    if (n[largest] < 0.0) n = -n;
    n.normalize();
    // u: the coordinate axis least along the normal, made perpendicular to it; v = n × u.
    int least = 0;
    n.cwiseAbs().minCoeff(&least);
    const Eigen::Vector3d e = Eigen::Vector3d::Unit(least);
    const Eigen::Vector3d u = (e - e.dot(n) * n).normalized();
    const Eigen::Vector3d v = n.cross(u);
    std::vector<Eigen::Vector2d> out;
    out.reserve(face.size());
    for (int i : face) out.emplace_back(u.dot(positions[size_t(i)]), v.dot(positions[size_t(i)]));
    return out;
}

} // namespace shatter::fracture
