#include <shatter/plugin/oriented/ShapeMatchingGroups.h>

#include <shatter/plugin/common/InputError.h>
#include <shatter/plugin/oriented/RotationExtraction.h>

#include <algorithm>
#include <atomic>
#include <string>

namespace shatter::oriented {

namespace {

std::atomic<std::uint64_t> nextId{1}; // ShapeMatchingGroups::connectionsVersion()

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
                                         const std::vector<std::pair<int, int>>& connections)
    : id_(nextId.fetch_add(1)) {
    build(particles, connections);
}

void ShapeMatchingGroups::rebuild(const OrientedParticles& particles,
                                  const std::vector<std::pair<int, int>>& connections) {
    build(particles, connections); // first: a throw leaves the groups as they were
    id_ = nextId.fetch_add(1);
}

void ShapeMatchingGroups::build(const OrientedParticles& particles,
                                const std::vector<std::pair<int, int>>& connections) {
    const int n = particles.size();
    // Each particle's neighbours in one flat list (counted, then filled: a torn part of
    // thousands of particles builds these in the frame of the tear).
    std::vector<int> start(size_t(n) + 1, 0);
    for (const auto& [a, b] : connections) {
        if (a < 0 || b < 0 || a >= n || b >= n)
            throw InputError("shape matching: connection (" + std::to_string(a) + ", " + std::to_string(b) +
                             ") names a particle outside [0, " + std::to_string(n) + ")");
        if (a == b) continue;
        ++start[size_t(a) + 1];
        ++start[size_t(b) + 1];
    }
    for (int g = 0; g < n; ++g) start[size_t(g) + 1] += start[size_t(g)];
    std::vector<int> neighbours(size_t(start.back()));
    std::vector<int> next(start.begin(), start.end() - 1);
    for (const auto& [a, b] : connections) {
        if (a == b) continue;
        neighbours[size_t(next[size_t(a)]++)] = b;
        neighbours[size_t(next[size_t(b)]++)] = a;
    }
    offsets_.clear();
    members_.clear();
    offsets_.reserve(size_t(n) + 1);
    members_.reserve(size_t(n) + neighbours.size());
    offsets_.push_back(0);
    for (int g = 0; g < n; ++g) {
        const auto first = neighbours.begin() + start[size_t(g)];
        const auto last = neighbours.begin() + start[size_t(g) + 1];
        std::sort(first, last);
        members_.push_back(g);
        members_.insert(members_.end(), first, std::unique(first, last));
        offsets_.push_back(int(members_.size()));
    }
    rotation_.assign(n, Eigen::Quaterniond::Identity());
    rotatedMoment_.clear(); // refreshMoments fills them
    fixed_.clear();
    updateRest(particles);
}

void ShapeMatchingGroups::updateRest(const OrientedParticles& particles) {
    const int n = size();
    totalMass_.assign(n, 0.0);
    restCentre_.assign(n, Eigen::Vector3d::Zero());
    restMomentInverse_.assign(n, Eigen::Matrix3d::Identity());
    slots_.resize(members_.size());
    for (int g = 0; g < n; ++g) updateRest(g, particles);
}

void ShapeMatchingGroups::updateRest(int g, const OrientedParticles& particles) {
    {
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
            Slot& slot = slots_[size_t(k)];
            slot.particle = members_[size_t(k)];
            slot.mass = particles.mass[slot.particle];
            slot.restOffset = particles.restPosition[slot.particle] - c;
            slot.weightedRestOffset = slot.mass * slot.restOffset;
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

template <typename Moment>
Eigen::Matrix3d ShapeMatchingGroups::momentAbout(int g, const OrientedParticles& particles,
                                                 std::span<const Eigen::Vector3d> x, const Moment& moment,
                                                 const Eigen::Vector3d& c) const {
    Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
    for (int j : members(g))
        A += moment(j) + particles.mass[j] * (x[j] - c) * (particles.restPosition[j] - restCentre_[g]).transpose();
    return A;
}

Eigen::Matrix3d ShapeMatchingGroups::moment(int g, const OrientedParticles& particles,
                                            std::span<const Eigen::Vector3d> x,
                                            std::span<const Eigen::Quaterniond> q) const {
    return momentAbout(g, particles, x, [&](int j) { return particles.moment(j, q[j]); }, centre(g, particles, x));
}

Eigen::Matrix3d ShapeMatchingGroups::deformation(int g, const OrientedParticles& particles,
                                                 std::span<const Eigen::Vector3d> x,
                                                 std::span<const Eigen::Quaterniond> q) const {
    return moment(g, particles, x, q) * restMomentInverse_[g];
}

std::vector<Eigen::Matrix3d> ShapeMatchingGroups::deformations(const OrientedParticles& particles,
                                                               std::span<const Eigen::Vector3d> x,
                                                               std::span<const Eigen::Quaterniond> q) const {
    std::vector<Eigen::Matrix3d> moments(static_cast<size_t>(particles.size()));
    for (int j = 0; j < particles.size(); ++j) moments[size_t(j)] = particles.moment(j, q[j]);
    std::vector<Eigen::Matrix3d> D(static_cast<size_t>(size()));
    for (int g = 0; g < size(); ++g)
        D[size_t(g)] = momentAbout(g, particles, x, [&](int j) -> const Eigen::Matrix3d& { return moments[size_t(j)]; },
                                   centre(g, particles, x)) *
                       restMomentInverse_[g];
    return D;
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
    fixed_.resize(size_t(particles.size()));
    for (int j = 0; j < particles.size(); ++j) {
        rotatedMoment_[size_t(j)] = particles.moment(j, q[j]);
        fixed_[size_t(j)] = particles.fixed[j];
    }
}

void ShapeMatchingGroups::project(int g, const OrientedParticles& particles, std::span<Eigen::Vector3d> x,
                                  std::span<Eigen::Quaterniond> q, double stiffness, int rotationIterations,
                                  double newtonStop) {
    // One pass: with o the centre particle's position (distant bodies keep their digits) and
    // Σ m_j r̄_j = 0, A = Σ (R_j C_j + m_j (x_j − o) r̄_jᵀ) and x_cm = o + Σ m_j (x_j − o) / M.
    // Plain sums over the group's contiguous slots into local scalars, which the compiler
    // keeps in registers (Eigen's 3×3 accumulator went through memory on every member).
    const Slot* const first = slots_.data() + offsets_[g];
    const Slot* const last = slots_.data() + offsets_[g + 1];
    const int centreParticle = first->particle;
    const Eigen::Vector3d origin = x[centreParticle];
    double a00 = 0, a10 = 0, a20 = 0, a01 = 0, a11 = 0, a21 = 0, a02 = 0, a12 = 0, a22 = 0;
    double s0 = 0, s1 = 0, s2 = 0;
    for (const Slot* s = first; s != last; ++s) {
        const double* C = rotatedMoment_[size_t(s->particle)].data(); // column-major
        const Eigen::Vector3d& xj = x[s->particle];
        const double d0 = xj.x() - origin.x(), d1 = xj.y() - origin.y(), d2 = xj.z() - origin.z();
        const double w0 = s->weightedRestOffset.x(), w1 = s->weightedRestOffset.y(), w2 = s->weightedRestOffset.z();
        a00 += C[0] + d0 * w0, a10 += C[1] + d1 * w0, a20 += C[2] + d2 * w0;
        a01 += C[3] + d0 * w1, a11 += C[4] + d1 * w1, a21 += C[5] + d2 * w1;
        a02 += C[6] + d0 * w2, a12 += C[7] + d1 * w2, a22 += C[8] + d2 * w2;
        s0 += s->mass * d0, s1 += s->mass * d1, s2 += s->mass * d2;
    }
    Eigen::Matrix3d A;
    A << a00, a01, a02, a10, a11, a12, a20, a21, a22;
    const Eigen::Vector3d sum(s0, s1, s2);
    const Eigen::Vector3d c = origin + sum / totalMass_[g];
    rotation_[g] = extractRotation(A, rotation_[g], rotationIterations, 1e-12, newtonStop);
    const Eigen::Matrix3d R = rotation_[g].toRotationMatrix();
    for (const Slot* s = first; s != last; ++s) {
        if (fixed_[size_t(s->particle)]) continue;
        Eigen::Vector3d& xj = x[s->particle];
        xj += stiffness * (R * s->restOffset + c - xj);
    }
    if (!fixed_[size_t(centreParticle)]) {
        Eigen::Quaterniond target = rotation_[g];
        if (target.dot(q[centreParticle]) < 0.0) target.coeffs() = -target.coeffs(); // shortest arc
        q[centreParticle] = turnedToward(q[centreParticle], target, stiffness);
        rotatedMoment_[size_t(centreParticle)] = particles.moment(centreParticle, q[centreParticle]);
    }
}

} // namespace shatter::oriented
