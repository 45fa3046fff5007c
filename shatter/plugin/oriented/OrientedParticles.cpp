#include <shatter/plugin/oriented/OrientedParticles.h>

#include <shatter/plugin/common/InputError.h>
#include <shatter/plugin/oriented/ParticleMoment.h>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace shatter::oriented {

void OrientedParticles::add(const Eigen::Vector3d& restCentre, double particleMass, const Eigen::Matrix3d& moment) {
    position.push_back(restCentre);
    orientation.push_back(Eigen::Quaterniond::Identity());
    velocity.push_back(Eigen::Vector3d::Zero());
    angularVelocity.push_back(Eigen::Vector3d::Zero());
    mass.push_back(particleMass);
    fixed.push_back(false);
    restPosition.push_back(restCentre);
    restMoment.push_back(moment);
}

Eigen::Vector3d OrientedParticles::linearMomentum() const {
    Eigen::Vector3d p = Eigen::Vector3d::Zero();
    for (int i = 0; i < size(); ++i) p += mass[i] * velocity[i];
    return p;
}

Eigen::Vector3d OrientedParticles::angularMomentum() const {
    Eigen::Vector3d L = Eigen::Vector3d::Zero();
    for (int i = 0; i < size(); ++i) {
        const Eigen::Matrix3d R = orientation[i].toRotationMatrix();
        const Eigen::Matrix3d inertia = R * inertiaFromMoment(restMoment[i]) * R.transpose();
        L += mass[i] * position[i].cross(velocity[i]) + inertia * angularVelocity[i];
    }
    return L;
}

double OrientedParticles::kineticEnergy() const {
    double e = 0.0;
    for (int i = 0; i < size(); ++i) {
        const Eigen::Matrix3d R = orientation[i].toRotationMatrix();
        const Eigen::Vector3d localSpin = R.transpose() * angularVelocity[i];
        e += 0.5 * mass[i] * velocity[i].squaredNorm() + 0.5 * localSpin.dot(inertiaFromMoment(restMoment[i]) * localSpin);
    }
    return e;
}

double OrientedParticles::restShapeError() const {
    double worst = 0.0;
    for (int i = 0; i < size(); ++i)
        for (int j = i + 1; j < size(); ++j)
            worst = std::max(worst, std::abs((position[i] - position[j]).norm() -
                                             (restPosition[i] - restPosition[j]).norm()));
    return worst;
}

OrientedParticles particlesFromPrimitives(const std::vector<geometry::ConvexPolyhedron>& primitives, double density,
                                          const std::string& object) {
    OrientedParticles particles;
    for (size_t i = 0; i < primitives.size(); ++i) {
        const geometry::MassProperties m = primitives[i].massProperties(density);
        if (!std::isfinite(m.mass) || !(m.mass > 0.0)) {
            std::ostringstream msg;
            msg << "object '" << object << "': primitive " << i << " has mass " << m.mass
                << " kg; every primitive needs a positive mass (check density and thickness)";
            throw InputError(msg.str());
        }
        particles.add(m.centerOfMass, m.mass, secondMoment(m));
    }
    return particles;
}

} // namespace shatter::oriented
