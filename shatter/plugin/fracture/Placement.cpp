#include <shatter/plugin/fracture/Placement.h>

#include <shatter/plugin/common/SettingCheck.h>
#include <shatter/plugin/fracture/Random.h>

#include <cmath>
#include <numbers>
#include <sstream>

namespace shatter::fracture {

namespace {

void requireFiniteVector(const std::string& body, const std::string& field, const Eigen::Vector3d& v) {
    if (v.allFinite()) return;
    std::ostringstream msg;
    msg << "body '" << body << "': " << field << " must be finite, got (" << v.x() << ", " << v.y() << ", " << v.z()
        << ")";
    throw InputError(msg.str());
}

} // namespace

void Placement::check(const std::string& body) const {
    requireFiniteVector(body, "fracture point", point);
    requireFiniteVector(body, "fracture normal", normal);
    requireSetting(normal.norm() > 0.0, body, "fracture normal length", "positive", normal.norm());
    requireSetting(std::isfinite(twist), body, "fracture twist", "finite", twist);
    requirePositive(body, "fracture pattern scale", scale);
}

Eigen::Matrix3d Placement::rotation() const {
    const Eigen::Vector3d axis = normal.normalized();
    // FromTwoVectors picks some perpendicular axis for the antiparallel case; deterministic.
    const Eigen::Quaterniond align = Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), axis);
    return (Eigen::AngleAxisd(twist, axis) * align).toRotationMatrix();
}

double seededTwist(std::uint64_t seed) { return 2.0 * std::numbers::pi * Random(seed).uniform(); }

Eigen::Vector3d thinnestAxis(const geometry::PhysicalMesh& body, const Eigen::Vector3d& impactNormal) {
    const auto principal = body.mass.principal(); // moments ascending: the last is the thinnest axis
    Eigen::Vector3d axis = principal.axes.col(2);
    if (axis.dot(impactNormal) < 0.0) axis = -axis;
    return axis;
}

} // namespace shatter::fracture
