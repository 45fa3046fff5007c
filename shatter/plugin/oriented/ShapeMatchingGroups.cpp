#include <shatter/plugin/oriented/ShapeMatchingGroups.h>

#include <shatter/plugin/common/InputError.h>
#include <shatter/plugin/oriented/RotationLanes.h>

#include <algorithm>
#include <atomic>
#include <cstring>
#include <string>

// The lane code takes and returns 32-byte vectors by value in always-inlined helpers, never
// across the ABI that GCC warns changed for such vectors.
#pragma GCC diagnostic ignored "-Wpsabi"

namespace shatter::oriented {

namespace {

std::atomic<std::uint64_t> nextId{1}; // ShapeMatchingGroups::connectionsVersion()

// slerp from q toward target by s, renormalised: the rare wide turn, out of line.
[[gnu::noinline]] Eigen::Quaterniond slerpedToward(const Eigen::Quaterniond& q, const Eigen::Quaterniond& target,
                                                   double s) {
    return q.slerp(s, target).normalized();
}

// q turned toward target by the fraction s of the arc between them: slerp, or (under about
// 1.6° apart, where the two differ by less than 1e-9 rad) the normalised linear blend, which
// spares slerp's inverse cosine and sines. Inlined into each group's projection (once per
// group and sweep).
SHATTER_LANES_INLINE Eigen::Quaterniond turnedToward(const Eigen::Quaterniond& q, const Eigen::Quaterniond& target,
                                                     double s) {
    if (s >= 1.0) return target;
    if (q.dot(target) < 0.9999) return slerpedToward(q, target, s);
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
    anyFixed_ = false;
    updateRest(particles);
    orderBatches();
}

void ShapeMatchingGroups::orderBatches() {
    // How far ahead of its first group a batch looks for the others: in a grid of groups
    // (each a particle and its neighbours) the nearest ones sharing no particle are three
    // apart along a row, so a batch of 4 needs 10; farther would cost locality for nothing.
    constexpr int kWindow = 32;
    const int n = size();
    order_.clear();
    order_.reserve(size_t(n));
    batchStart_.assign(1, 0);
    std::vector<int> holder(size_t(n), -1); // per particle: the last batch that holds it
    std::vector<unsigned char> placed(size_t(n), 0);
    for (int first = 0; first < n;) {
        const int b = batches();
        const int end = std::min(n, first + kWindow);
        for (int g = first; g < end && int(order_.size()) - batchStart_.back() < kRotationLanes; ++g) {
            if (placed[size_t(g)]) continue;
            const auto group = members(g);
            if (std::any_of(group.begin(), group.end(), [&](int j) { return holder[size_t(j)] == b; })) continue;
            for (int j : group) holder[size_t(j)] = b;
            placed[size_t(g)] = 1;
            order_.push_back(g);
        }
        batchStart_.push_back(int(order_.size()));
        while (first < n && placed[size_t(first)]) ++first;
    }
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
            const int j = members_[size_t(k)];
            const Eigen::Vector3d restOffset = particles.restPosition[j] - c;
            for (int e = 0; e < 3; ++e) slot.restOffsetMass[e] = restOffset[e];
            slot.restOffsetMass[3] = particles.mass[j];
        }
        // Positive definite for any particle of positive volume (its own moment is).
        restMomentInverse_[g] = restA.inverse();
    }
}

// Always inlined, so that each path's projection sums on its own instruction set.
template <bool wide, typename Moment>
SHATTER_LANES_INLINE ShapeMatchingGroups::Sums ShapeMatchingGroups::sums(int g, std::span<const Eigen::Vector3d> x,
                                                                         const Moment& moment) const {
    // One pass: with o the centre particle's position (distant bodies keep their digits) and
    // Σ m_j r̄_j = 0, A = Σ R_j C_j + Σ (x_j − o) m_j r̄_jᵀ and x_cm = o + Σ m_j (x_j − o) / M.
    // The second and third sums are one 3 × 4 outer product per member, (x_j − o) times
    // (m_j r̄_j, m_j) (from the slot), kept as three rows of 4 lanes, each a broadcast times
    // that row; Σ R_j C_j is summed as its first 8 entries (column-major) in two rows of 4 and the
    // ninth alone. Each entry is summed member by member as the plain sum would be: the same
    // bits on both paths, in a third of the instructions of summing the 21 scalars one by one.
    using Row = DoubleLanes<4>;
    const LaneMask<4> massLane{0, 0, 0, -1};
    const int* const particle = members_.data() + offsets_[g];
    const Slot* const first = slots_.data() + offsets_[g];
    const Eigen::Vector3d origin = x[*particle];
    const Row ox = broadcast<4>(origin.x()), oy = broadcast<4>(origin.y()), oz = broadcast<4>(origin.z());
    Row r0{}, r1{}, r2{}, c0{}, c1{};
    double c8 = 0.0;
    const int count = offsets_[g + 1] - offsets_[g];
    for (int k = 0; k < count; ++k) {
        const Slot* const s = first + k;
        const int j = particle[k];
        const Eigen::Vector3d& xj = x[j];
        Row w;
        std::memcpy(&w, s->restOffsetMass, sizeof w);
        w *= select<4>(massLane, broadcast<4>(1.0), broadcast<4>(w[3])); // (m r̄, m)
        if constexpr (wide) { // x_j − o in every lane: a broadcast load and a 4-wide subtraction
            r0 += (broadcast<4>(xj.x()) - ox) * w, r1 += (broadcast<4>(xj.y()) - oy) * w;
            r2 += (broadcast<4>(xj.z()) - oz) * w;
        } else { // 2-wide halves: a scalar subtraction, then the broadcast
            const double dx = xj.x() - origin.x(), dy = xj.y() - origin.y(), dz = xj.z() - origin.z();
            r0 += dx * w, r1 += dy * w, r2 += dz * w;
        }
        const auto& rotated = moment(j); // a matrix, or a reference to one
        const double* C = rotated.data();          // column-major
        Row ca, cb;
        std::memcpy(&ca, C, sizeof ca);
        std::memcpy(&cb, C + 4, sizeof cb);
        c0 += ca, c1 += cb, c8 += C[8];
    }
    // ΣC column-major: c0 = (C00, C10, C20, C01), c1 = (C11, C21, C02, C12), c8 = C22.
    Sums out;
    out.A << r0[0] + c0[0], r0[1] + c0[3], r0[2] + c1[2], //
        r1[0] + c0[1], r1[1] + c1[0], r1[2] + c1[3],      //
        r2[0] + c0[2], r2[1] + c1[1], r2[2] + c8;
    out.centre = origin + Eigen::Vector3d(r0[3], r1[3], r2[3]) / totalMass_[g];
    return out;
}

Eigen::Matrix3d ShapeMatchingGroups::moment(int g, const OrientedParticles& particles,
                                            std::span<const Eigen::Vector3d> x,
                                            std::span<const Eigen::Quaterniond> q) const {
    return sums<false>(g, x, [&](int j) { return particles.moment(j, q[j]); }).A;
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
        D[size_t(g)] = sums<false>(g, x, [&](int j) -> const Eigen::Matrix3d& { return moments[size_t(j)]; }).A *
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
    anyFixed_ = false;
    for (int j = 0; j < particles.size(); ++j) {
        rotatedMoment_[size_t(j)] = particles.moment(j, q[j]);
        fixed_[size_t(j)] = particles.fixed[j];
        anyFixed_ = anyFixed_ || particles.fixed[j];
    }
}

// Group g's projection, one batch at a time, compiled into each path's sweep (and into
// project()): always inlined, so that each copy is built for its instruction set.
[[gnu::always_inline]] inline void ShapeMatchingGroups::projectBatch(std::span<const int> groups,
                                                                     const OrientedParticles& particles,
                                                                     std::span<Eigen::Vector3d> x,
                                                                     std::span<Eigen::Quaterniond> q,
                                                                     double stiffness, int rotationIterations,
                                                                     double newtonStop, SimdPath path) {
    using Row = DoubleLanes<4>;
    const int count = int(groups.size());
    // Each group's sums are set into its lane of the fits (extractRotations's bits), which
    // then run on all four lanes at once.
    RotationLanes fits;
    Eigen::Vector3d centre[kRotationLanes];
    for (int l = 0; l < kRotationLanes; ++l) {
        if (l >= count) { // unused lanes: a fit with nothing to fit
            fits.set(l, Eigen::Matrix3d::Zero(), Eigen::Quaterniond::Identity());
            continue;
        }
        const auto moment = [&](int j) -> const Eigen::Matrix3d& { return rotatedMoment_[size_t(j)]; };
        const Sums sum = path == SimdPath::Avx2 ? sums<true>(groups[l], x, moment) : sums<false>(groups[l], x, moment);
        fits.set(l, sum.A, rotation_[groups[l]]);
        centre[l] = sum.centre;
    }
    fitRotations(fits, count, rotationIterations, 1e-12, newtonStop, path);
    for (int l = 0; l < count; ++l) {
        const int g = groups[l];
        const Eigen::Quaterniond fit = fits.answer(l);
        rotation_[g] = fit;
        const int* const particle = members_.data() + offsets_[g];
        const Slot* const first = slots_.data() + offsets_[g];
        const int centreParticle = *particle;
        const int members = offsets_[g + 1] - offsets_[g];
        // A body with no fixed particle (most) skips the test per member.
        const bool anyFixed = anyFixed_;
        if (path == SimdPath::Portable) {
            // The same update in Eigen's 3-vectors, the same bits (Eigen's order, below): on
            // SSE2 the 4-lane rows went through the stack (x_j built from 3 loads), 35% slower.
            const Eigen::Matrix3d R = fit.toRotationMatrix();
            for (int k = 0; k < members; ++k) {
                const int j = particle[k];
                if (anyFixed && fixed_[size_t(j)]) continue;
                Eigen::Vector3d& xj = x[j];
                xj += stiffness * (R * Eigen::Map<const Eigen::Vector3d>(first[k].restOffsetMass) + centre[l] - xj);
            }
        } else {
            // x_j += k (R r̄_j + c − x_j) with x_j, R r̄_j and c as rows of 4 (the last lane
            // idle). R r̄_j in the order of Eigen's 3 × 3 product, whose bits the solver had: its
            // first two rows as (R₀₀ r̄_x + R₀₁ r̄_y) + R₀₂ r̄_z (a packet), the third as
            // R₂₀ r̄_x + (R₂₁ r̄_y + R₂₂ r̄_z), which is (R₂₁ r̄_y + R₂₂ r̄_z) + R₂₀ r̄_x: so with
            // r̄ permuted per lane (one instruction each) every lane is (a + b) + c, no blend.
            const Eigen::Matrix3d R = fit.toRotationMatrix();
            const Row Ra{R(0, 0), R(1, 0), R(2, 1), 0.0}, Rb{R(0, 1), R(1, 1), R(2, 2), 0.0},
                Rc{R(0, 2), R(1, 2), R(2, 0), 0.0};
            const Row c{centre[l].x(), centre[l].y(), centre[l].z(), 0.0};
            for (int k = 0; k < members; ++k) {
                const Slot* const s = first + k;
                const int j = particle[k];
                if (anyFixed && fixed_[size_t(j)]) continue;
                double* const xj = x[j].data();
                Row moved{xj[0], xj[1], xj[2], 0.0};
                Row r;
                std::memcpy(&r, s->restOffsetMass, sizeof r);
                const Row goal = (Ra * __builtin_shufflevector(r, r, 0, 0, 1, 3) +
                                  Rb * __builtin_shufflevector(r, r, 1, 1, 2, 3)) +
                                 Rc * __builtin_shufflevector(r, r, 2, 2, 0, 3);
                moved += stiffness * (goal + c - moved);
                xj[0] = moved[0], xj[1] = moved[1], xj[2] = moved[2];
            }
        }
        if (!anyFixed || !fixed_[size_t(centreParticle)]) {
            Eigen::Quaterniond target = fit;
            if (target.dot(q[centreParticle]) < 0.0) target.coeffs() = -target.coeffs(); // shortest arc
            q[centreParticle] = turnedToward(q[centreParticle], target, stiffness);
            rotatedMoment_[size_t(centreParticle)] = particles.moment(centreParticle, q[centreParticle]);
        }
    }
}

void ShapeMatchingGroups::project(int g, const OrientedParticles& particles, std::span<Eigen::Vector3d> x,
                                  std::span<Eigen::Quaterniond> q, double stiffness, int rotationIterations,
                                  double newtonStop) {
    projectBatch({&g, 1}, particles, x, q, stiffness, rotationIterations, newtonStop, SimdPath::Portable);
}

void ShapeMatchingGroups::projectAll(const OrientedParticles& particles, std::span<Eigen::Vector3d> x,
                                     std::span<Eigen::Quaterniond> q, double stiffness, int rotationIterations,
                                     double newtonStop, SimdPath path) {
    if (!simdPathAvailable(path))
        throw InputError("shape matching: projectAll on the AVX2 path on a processor without AVX2");
    path == SimdPath::Avx2 ? projectAllAvx2(particles, x, q, stiffness, rotationIterations, newtonStop)
                           : projectAllPortable(particles, x, q, stiffness, rotationIterations, newtonStop);
}

void ShapeMatchingGroups::projectAllPortable(const OrientedParticles& particles, std::span<Eigen::Vector3d> x,
                                             std::span<Eigen::Quaterniond> q, double stiffness,
                                             int rotationIterations, double newtonStop) {
    for (int b = 0; b < batches(); ++b)
        projectBatch(batch(b), particles, x, q, stiffness, rotationIterations, newtonStop, SimdPath::Portable);
}

SHATTER_AVX2 void ShapeMatchingGroups::projectAllAvx2(const OrientedParticles& particles,
                                                      std::span<Eigen::Vector3d> x,
                                                      std::span<Eigen::Quaterniond> q, double stiffness,
                                                      int rotationIterations, double newtonStop) {
    for (int b = 0; b < batches(); ++b)
        projectBatch(batch(b), particles, x, q, stiffness, rotationIterations, newtonStop, SimdPath::Avx2);
}

} // namespace shatter::oriented
