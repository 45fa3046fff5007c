#include <shatter/plugin/oriented/PairConstraints.h>

#include <shatter/plugin/oriented/ParticleMoment.h>

namespace shatter::oriented {

namespace {

double inverseMass(const OrientedParticles& p, int i) { return p.fixed[i] ? 0.0 : 1.0 / p.mass[i]; }

// 1 / (axisᵀ I axis) for particle i at orientation q: how easily it turns about `axis`.
double inverseInertia(const OrientedParticles& p, int i, const Eigen::Quaterniond& q, const Eigen::Vector3d& axis) {
    if (p.fixed[i]) return 0.0;
    const Eigen::Vector3d local = q.conjugate() * axis;
    return 1.0 / local.dot(inertiaFromMoment(p.restMoment[i]) * local);
}

} // namespace

void StretchConstraint::project(const OrientedParticles& particles, std::span<Eigen::Vector3d> x) const {
    const double wa = inverseMass(particles, a), wb = inverseMass(particles, b);
    const Eigen::Vector3d d = x[b] - x[a];
    const double length = d.norm();
    if (wa + wb == 0.0 || length == 0.0) return;
    const Eigen::Vector3d correction = stiffness * (length - restLength) / (length * (wa + wb)) * d;
    x[a] += wa * correction;
    x[b] -= wb * correction;
}

void BendConstraint::project(const OrientedParticles& particles, std::span<Eigen::Quaterniond> q) const {
    Eigen::Quaterniond relative = q[a].conjugate() * q[b]; // identity at rest
    if (relative.w() < 0.0) relative.coeffs() = -relative.coeffs();
    const Eigen::AngleAxisd turn(relative);
    if (turn.angle() == 0.0) return;
    const Eigen::Vector3d axis = q[a] * turn.axis(); // world axis of b's excess rotation
    const double wa = inverseInertia(particles, a, q[a], axis), wb = inverseInertia(particles, b, q[b], axis);
    if (wa + wb == 0.0) return;
    const double angle = stiffness * turn.angle();
    q[a] = Eigen::Quaterniond(Eigen::AngleAxisd(angle * wa / (wa + wb), axis)) * q[a];
    q[b] = Eigen::Quaterniond(Eigen::AngleAxisd(-angle * wb / (wa + wb), axis)) * q[b];
    q[a].normalize();
    q[b].normalize();
}

} // namespace shatter::oriented
