#include <shatter/plugin/oriented/ShapeMatchingGroups.h>

#include <shatter/plugin/common/InputError.h>
#include <shatter/plugin/oriented/RotationExtraction.h>

#include <algorithm>
#include <string>

namespace shatter::oriented {

namespace {

// q turned toward target by the fraction s of the arc between them: slerp, or (under about
// 1.6° apart, where the two differ by less than 1e-9 rad) the normalised linear blend, which
// spares slerp's inverse cosine and sines.
Eigen::Quaterniond turnedToward(const Eigen::Quaterniond& q, const Eigen::Quaterniond& target, double s) {
    if (s >= 1.0) return target;
    if (q.dot(target) < 0.9999) return q.slerp(s, target).normalized();
    return Eigen::Quaterniond(q.coeffs() + s * (target.coeffs() - q.coeffs())).normalized();
}

} // namespace

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
    restOffset_.resize(members_.size());
    weightedRestOffset_.resize(members_.size());
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
        for (int k = offsets_[g]; k < offsets_[g + 1]; ++k) {
            const int j = members_[size_t(k)];
            restOffset_[size_t(k)] = particles.restPosition[j] - c;
            weightedRestOffset_[size_t(k)] = particles.mass[j] * restOffset_[size_t(k)];
        }
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

bool ShapeMatchingGroups::connected(int a, int b) const {
    const auto group = members(a);
    return std::binary_search(group.begin() + 1, group.end(), b);
}

void ShapeMatchingGroups::refreshMoments(const OrientedParticles& particles, std::span<const Eigen::Quaterniond> q) {
    rotatedMoment_.resize(size_t(particles.size()));
    for (int j = 0; j < particles.size(); ++j) rotatedMoment_[size_t(j)] = particles.moment(j, q[j]);
}

void ShapeMatchingGroups::project(int g, const OrientedParticles& particles, std::span<Eigen::Vector3d> x,
                                  std::span<Eigen::Quaterniond> q, double stiffness, int rotationIterations) {
    // One pass: with o the centre particle's position (distant bodies keep their digits) and
    // Σ m_j r̄_j = 0, A = Σ (R_j C_j + m_j (x_j − o) r̄_jᵀ) and x_cm = o + Σ m_j (x_j − o) / M.
    const int first = offsets_[g], last = offsets_[g + 1];
    const int centreParticle = members_[size_t(first)];
    const Eigen::Vector3d origin = x[centreParticle];
    Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (int k = first; k < last; ++k) {
        const int j = members_[size_t(k)];
        const Eigen::Vector3d d = x[j] - origin;
        A += rotatedMoment_[size_t(j)] + d * weightedRestOffset_[size_t(k)].transpose();
        sum += particles.mass[j] * d;
    }
    const Eigen::Vector3d c = origin + sum / totalMass_[g];
    rotation_[g] = extractRotation(A, rotation_[g], rotationIterations);
    const Eigen::Matrix3d R = rotation_[g].toRotationMatrix();
    for (int k = first; k < last; ++k) {
        const int j = members_[size_t(k)];
        if (particles.fixed[j]) continue;
        const Eigen::Vector3d goal = R * restOffset_[size_t(k)] + c;
        x[j] += stiffness * (goal - x[j]);
    }
    if (!particles.fixed[centreParticle]) {
        Eigen::Quaterniond target = rotation_[g];
        if (target.dot(q[centreParticle]) < 0.0) target.coeffs() = -target.coeffs(); // shortest arc
        q[centreParticle] = turnedToward(q[centreParticle], target, stiffness);
        rotatedMoment_[size_t(centreParticle)] = particles.moment(centreParticle, q[centreParticle]);
    }
}

} // namespace shatter::oriented
