#include <shatter/plugin/oriented/ShapeMatchingGroups.h>

#include <shatter/plugin/common/InputError.h>
#include <shatter/plugin/oriented/RotationExtraction.h>

#include <algorithm>
#include <string>

namespace shatter::oriented {

ShapeMatchingGroups::ShapeMatchingGroups(const OrientedParticles& particles,
                                         const std::vector<std::pair<int, int>>& connections) {
    const int n = particles.size();
    std::vector<std::vector<int>> neighbours(n);
    for (const auto& [a, b] : connections) {
        if (a < 0 || b < 0 || a >= n || b >= n)
            throw InputError("shape matching: connection (" + std::to_string(a) + ", " + std::to_string(b) +
                             ") names a particle outside [0, " + std::to_string(n) + ")");
        if (a == b) continue;
        neighbours[a].push_back(b);
        neighbours[b].push_back(a);
    }
    offsets_.push_back(0);
    for (int g = 0; g < n; ++g) {
        auto& list = neighbours[g];
        std::sort(list.begin(), list.end());
        list.erase(std::unique(list.begin(), list.end()), list.end());
        members_.push_back(g);
        members_.insert(members_.end(), list.begin(), list.end());
        offsets_.push_back(int(members_.size()));
    }
    rotation_.assign(n, Eigen::Quaterniond::Identity());
    updateRest(particles);
}

void ShapeMatchingGroups::updateRest(const OrientedParticles& particles) {
    const int n = size();
    totalMass_.assign(n, 0.0);
    restCentre_.assign(n, Eigen::Vector3d::Zero());
    restMomentInverse_.assign(n, Eigen::Matrix3d::Identity());
    for (int g = 0; g < n; ++g) {
        double M = 0.0;
        Eigen::Vector3d c = Eigen::Vector3d::Zero();
        for (int j : members(g)) {
            M += particles.mass[j];
            c += particles.mass[j] * particles.restPosition[j];
        }
        c /= M;
        Eigen::Matrix3d restA = Eigen::Matrix3d::Zero();
        for (int j : members(g)) {
            const Eigen::Vector3d r = particles.restPosition[j] - c;
            restA += particles.restMoment[j] + particles.mass[j] * r * r.transpose();
        }
        totalMass_[g] = M;
        restCentre_[g] = c;
        // Positive definite for any particle of positive volume (its own moment is).
        restMomentInverse_[g] = restA.inverse();
    }
}

Eigen::Vector3d ShapeMatchingGroups::centre(int g, const OrientedParticles& particles,
                                            std::span<const Eigen::Vector3d> x) const {
    // Relative to the centre particle, so distant bodies keep their digits.
    const Eigen::Vector3d& origin = x[members(g)[0]];
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (int j : members(g)) c += particles.mass[j] * (x[j] - origin);
    return origin + c / totalMass_[g];
}

Eigen::Matrix3d ShapeMatchingGroups::moment(int g, const OrientedParticles& particles,
                                            std::span<const Eigen::Vector3d> x,
                                            std::span<const Eigen::Quaterniond> q) const {
    return momentAbout(g, particles, x, q, centre(g, particles, x));
}

Eigen::Matrix3d ShapeMatchingGroups::momentAbout(int g, const OrientedParticles& particles,
                                                 std::span<const Eigen::Vector3d> x,
                                                 std::span<const Eigen::Quaterniond> q, const Eigen::Vector3d& c) const {
    Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
    for (int j : members(g))
        A += particles.moment(j, q[j]) +
             particles.mass[j] * (x[j] - c) * (particles.restPosition[j] - restCentre_[g]).transpose();
    return A;
}

Eigen::Matrix3d ShapeMatchingGroups::deformation(int g, const OrientedParticles& particles,
                                                 std::span<const Eigen::Vector3d> x,
                                                 std::span<const Eigen::Quaterniond> q) const {
    return moment(g, particles, x, q) * restMomentInverse_[g];
}

Eigen::Quaterniond ShapeMatchingGroups::fitRotation(int g, const OrientedParticles& particles,
                                                    std::span<const Eigen::Vector3d> x,
                                                    std::span<const Eigen::Quaterniond> q, int rotationIterations) {
    rotation_[g] = extractRotation(moment(g, particles, x, q), rotation_[g], rotationIterations);
    return rotation_[g];
}

void ShapeMatchingGroups::project(int g, const OrientedParticles& particles, std::span<Eigen::Vector3d> x,
                                  std::span<Eigen::Quaterniond> q, double stiffness, int rotationIterations) {
    const Eigen::Vector3d c = centre(g, particles, x);
    rotation_[g] = extractRotation(momentAbout(g, particles, x, q, c), rotation_[g], rotationIterations);
    const Eigen::Matrix3d R = rotation_[g].toRotationMatrix();
    for (int j : members(g)) {
        if (particles.fixed[j]) continue;
        const Eigen::Vector3d goal = R * (particles.restPosition[j] - restCentre_[g]) + c;
        x[j] += stiffness * (goal - x[j]);
    }
    const int centreParticle = members(g)[0];
    if (!particles.fixed[centreParticle]) {
        Eigen::Quaterniond target = rotation_[g];
        if (target.dot(q[centreParticle]) < 0.0) target.coeffs() = -target.coeffs(); // shortest arc
        q[centreParticle] = stiffness >= 1.0 ? target : q[centreParticle].slerp(stiffness, target);
        q[centreParticle].normalize();
    }
}

} // namespace shatter::oriented
