#include <shatter/plugin/oriented/ParticleMoment.h>

namespace shatter::oriented {

Eigen::Matrix3d secondMoment(const geometry::MassProperties& mass) {
    return 0.5 * mass.inertia.trace() * Eigen::Matrix3d::Identity() - mass.inertia;
}

Eigen::Matrix3d sphereMoment(double mass, double radius) {
    return mass * radius * radius / 5.0 * Eigen::Matrix3d::Identity();
}

Eigen::Matrix3d ellipsoidMoment(double mass, const Eigen::Vector3d& semiAxes) {
    return (mass / 5.0 * semiAxes.cwiseProduct(semiAxes)).asDiagonal();
}

Eigen::Matrix3d inertiaFromMoment(const Eigen::Matrix3d& C) { return C.trace() * Eigen::Matrix3d::Identity() - C; }

} // namespace shatter::oriented
