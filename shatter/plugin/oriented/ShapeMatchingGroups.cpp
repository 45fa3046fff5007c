#include <shatter/plugin/oriented/ShapeMatchingGroups.h>

#include <shatter/plugin/common/InputError.h>
#include <shatter/plugin/oriented/RotationLanes.h>

#include <algorithm>
#include <atomic>
#include <cstring>
#include <stdexcept>
#include <string>

// The lane code takes and returns 32-byte vectors by value in always-inlined helpers, never
// across the ABI that GCC warns changed for such vectors.
#pragma GCC diagnostic ignored "-Wpsabi"

namespace shatter::oriented {

namespace {

std::atomic<std::uint64_t> nextId{1}; // ShapeMatchingGroups::connectionsVersion()

// The layouts the flat reads and copies below assume: positions as 3 packed doubles (read with
// stride 3), matrices as 9 column-major doubles (copied 4 + 4 + 1), quaternions as their
// coefficients (x, y, z, w) in 4 doubles (copied as one 4-lane row).
static_assert(sizeof(Eigen::Vector3d) == 3 * sizeof(double));
static_assert(sizeof(Eigen::Matrix3d) == 9 * sizeof(double) && !Eigen::Matrix3d::IsRowMajor);
static_assert(sizeof(Eigen::Quaterniond) == 4 * sizeof(double));

// x as a flat array of doubles, x_j at 3 j (no dereference: an empty span gives its null or
// end pointer, never read).
double* flat(std::span<Eigen::Vector3d> x) { return reinterpret_cast<double*>(x.data()); }
const double* flat(std::span<const Eigen::Vector3d> x) { return reinterpret_cast<const double*>(x.data()); }

// slerp from q toward target by s, renormalised: the rare wide turn, out of line.
[[gnu::noinline]] Eigen::Quaterniond slerpedToward(const Eigen::Quaterniond& q, const Eigen::Quaterniond& target,
                                                   double s) {
    return q.slerp(s, target).normalized();
}

// Lane l's moment R(q_l) C_{p[l]} (particles.moment's bits), with q as lanes of its coefficients
// (x, y, z, w) and C the particles' rest moments: R as Eigen's toRotationMatrix, the 3 × 3
// product's first two rows as (a + b) + c and its third as a + (b + c), as Eigen's product.
// Out per lane, ready to store (storeMoment): its entries 0-3 and 4-7 (column-major) as rows
// first[l] and second[l], and entry 8 as last[l]. Every p[l] must be a particle (an idle
// lane repeats another's).
SHATTER_LANES_INLINE void rotatedMoments(const DoubleLanes<4> (&q)[4], const int (&p)[kRotationLanes],
                                         const OrientedParticles& particles, DoubleLanes<4> (&first)[4],
                                         DoubleLanes<4> (&second)[4], DoubleLanes<4>& last) {
    using Row = DoubleLanes<4>;
    Row r[9];
    rotationMatrices<4>(q[3], q[0], q[1], q[2], r);
    // C (column-major) as lanes: c[j][i] = C(i, j).
#pragma GCC unroll 4
    for (int l = 0; l < kRotationLanes; ++l) {
        const double* const C = particles.restMoment[p[l]].data();
        std::memcpy(&first[l], C, sizeof(Row));
        std::memcpy(&second[l], C + 4, sizeof(Row));
        last[l] = C[8];
    }
    transpose(first);
    transpose(second);
    const Row c[3][3] = {{first[0], first[1], first[2]}, {first[3], second[0], second[1]}, {second[2], second[3], last}};
    Row m[3][3]; // m[j][i] = M(i, j)
    for (int j = 0; j < 3; ++j) {
        for (int i = 0; i < 2; ++i) m[j][i] = (r[3 * i] * c[j][0] + r[3 * i + 1] * c[j][1]) + r[3 * i + 2] * c[j][2];
        m[j][2] = r[6] * c[j][0] + (r[7] * c[j][1] + r[8] * c[j][2]);
    }
    first[0] = m[0][0], first[1] = m[0][1], first[2] = m[0][2], first[3] = m[1][0];
    second[0] = m[1][1], second[1] = m[1][2], second[2] = m[2][0], second[3] = m[2][1];
    transpose(first);
    transpose(second);
    last = m[2][2];
}

// Lane l of rotatedMoments' answer into M.
SHATTER_LANES_INLINE void storeMoment(int l, const DoubleLanes<4> (&first)[4], const DoubleLanes<4> (&second)[4],
                                      const DoubleLanes<4>& last, Eigen::Matrix3d& M) {
    std::memcpy(M.data(), &first[l], sizeof first[l]);
    std::memcpy(M.data() + 4, &second[l], sizeof second[l]);
    M(2, 2) = last[l];
}

// The centres of a batch's groups turned toward their fits by the fraction s of the arc
// between them, and their moments R_c C_c (moment(c, q_c)), on the batch's lanes. The turn is
// slerp for the rare wide one (lane by lane, slerpedToward) and else, under about 1.6° apart
// where the two differ by less than 1e-9 rad, the normalised linear blend, which spares slerp's
// inverse cosine and sines. Every lane does the operations of Eigen's code for one centre in
// its order (4-vector dot products and norms as ((x + z) + (y + w)), the 3 × 3 product's
// first two rows as (a + b) + c and its third as a + (b + c)): the same bits in about a third of
// the instructions, and the four square roots and divisions overlap. Lane l turns when
// turns[l] is set (a group of the batch whose centre is not fixed); the others are read (every
// centre[l] must be a particle: an idle lane repeats another's) but not written.
SHATTER_LANES_INLINE void turnCentres(const RotationLanes& fits, const int (&centre)[kRotationLanes],
                                      const LaneMask<4>& turns, double s, const OrientedParticles& particles,
                                      std::span<Eigen::Quaterniond> q, Eigen::Matrix3d* moments) {
    using Row = DoubleLanes<4>;
    // The centres' orientations as lanes of their coefficients (x, y, z, w).
    Row from[4];
#pragma GCC unroll 4
    for (int l = 0; l < kRotationLanes; ++l) std::memcpy(&from[l], q[centre[l]].coeffs().data(), sizeof(Row));
    transpose(from);
    const auto dot = [&](const Row (&a)[4]) { return (a[0] * from[0] + a[2] * from[2]) + (a[1] * from[1] + a[3] * from[3]); };
    // The fit, on the shortest arc from the centre's orientation.
    const Row fit[4] = {fits.x, fits.y, fits.z, fits.w};
    const LaneMask<4> flip = dot(fit) < 0.0;
    Row target[4], to[4];
    for (int e = 0; e < 4; ++e) target[e] = select<4>(flip, -fit[e], fit[e]);
    if (s >= 1.0) {
        for (int e = 0; e < 4; ++e) to[e] = target[e];
    } else {
        const LaneMask<4> wide = dot(target) < 0.9999;
        Row blend[4];
        for (int e = 0; e < 4; ++e) blend[e] = from[e] + s * (target[e] - from[e]);
        const Row norm2 = (blend[0] * blend[0] + blend[2] * blend[2]) + (blend[1] * blend[1] + blend[3] * blend[3]);
        Row norm{};
#pragma GCC unroll 4
        for (int l = 0; l < kRotationLanes; ++l) norm[l] = std::sqrt(norm2[l]);
        for (int e = 0; e < 4; ++e) to[e] = select<4>(norm2 > 0.0, blend[e] / norm, blend[e]);
        const LaneMask<4> slerps = turns & wide;
        for (int l = 0; l < kRotationLanes; ++l) {
            if (!slerps[l]) continue;
            const Eigen::Quaterniond slerped =
                slerpedToward(Eigen::Quaterniond(from[3][l], from[0][l], from[1][l], from[2][l]),
                              Eigen::Quaterniond(target[3][l], target[0][l], target[1][l], target[2][l]), s);
            for (int e = 0; e < 4; ++e) to[e][l] = slerped.coeffs()[e];
        }
    }
    Row first[4], second[4], last;
    rotatedMoments(to, centre, particles, first, second, last); // R_c C_c
    Row turned[4] = {to[0], to[1], to[2], to[3]};
    transpose(turned);
#pragma GCC unroll 4
    for (int l = 0; l < kRotationLanes; ++l) {
        if (!turns[l]) continue;
        std::memcpy(q[centre[l]].coeffs().data(), &turned[l], sizeof(Row));
        storeMoment(l, first, second, last, moments[centre[l]]);
    }
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
    restPoint_.resize(size_t(particles.size()));
    mass_.resize(size_t(particles.size()));
    for (int j = 0; j < particles.size(); ++j) {
        const Eigen::Vector3d& r = particles.restPosition[j];
        restPoint_[size_t(j)] = PaddedPoint{{r.x(), r.y(), r.z(), 1.0}};
        mass_[size_t(j)] = particles.mass[j];
    }
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
        // Positive definite for any particle of positive volume (its own moment is).
        restMomentInverse_[g] = restA.inverse();
    }
}

// Always inlined, so that each path's projection sums on its own instruction set.
template <bool wide, int stride, typename Moment>
SHATTER_LANES_INLINE ShapeMatchingGroups::Sums ShapeMatchingGroups::sums(int g, const double* x,
                                                                         const Moment& moment) const {
    // One pass: with o the centre particle's position (distant bodies keep their digits) and
    // Σ m_j r̄_j = 0, A = Σ R_j C_j + Σ (x_j − o) m_j r̄_jᵀ and x_cm = o + Σ m_j (x_j − o) / M.
    // The second and third sums are one 3 × 4 outer product per member, (x_j − o) times
    // (m_j r̄_j, m_j) = ((x̄_j, 1) − (x̄_cm, 0)) m_j, kept as three rows of 4 lanes, each a broadcast times
    // that row; Σ R_j C_j is summed as its first 8 entries (column-major) in two rows of 4 and the
    // ninth alone. Each entry is summed member by member as the plain sum would be: the same
    // bits on both paths, in a third of the instructions of summing the 21 scalars one by one.
    using Row = DoubleLanes<4>;
    const int* const particle = members_.data() + offsets_[g];
    const double* const rest = restPoint_.data()->v;
    const double* const mass = mass_.data();
    const Row restCentre{restCentre_[g].x(), restCentre_[g].y(), restCentre_[g].z(), 0.0};
    const Eigen::Vector3d origin = Eigen::Map<const Eigen::Vector3d>(x + stride * std::ptrdiff_t(*particle));
    const Row ox = broadcast<4>(origin.x()), oy = broadcast<4>(origin.y()), oz = broadcast<4>(origin.z());
    Row r0{}, r1{}, r2{}, c0{}, c1{};
    double c8 = 0.0;
    const int count = offsets_[g + 1] - offsets_[g];
    for (int k = 0; k < count; ++k) {
        const int j = particle[k];
        // AVX2: a 64-bit index, no sign extension. SSE2: an int one (the 64-bit one cost a
        // second load and scaling of j a member there).
        const double* const xj = wide ? x + stride * std::ptrdiff_t(j) : x + stride * j;
        Row w; // (r̄, 1) m = (m r̄, m): updateRest's r̄ and the product m r̄ that was stored before
        std::memcpy(&w, wide ? rest + 4 * std::ptrdiff_t(j) : rest + 4 * j, sizeof w);
        w = (w - restCentre) * mass[j];
        if constexpr (wide && stride == 4) { // x_j − o from one 4-lane load and subtraction, each lane broadcast
            Row d;
            std::memcpy(&d, xj, sizeof d);
            d -= Row{origin.x(), origin.y(), origin.z(), 0.0};
            r0 += __builtin_shufflevector(d, d, 0, 0, 0, 0) * w;
            r1 += __builtin_shufflevector(d, d, 1, 1, 1, 1) * w;
            r2 += __builtin_shufflevector(d, d, 2, 2, 2, 2) * w;
        } else if constexpr (wide) { // x_j − o in every lane: a broadcast and a 4-wide subtraction
            // x and y broadcast from one 2-lane load, z from memory: 4 instructions. (Three
            // scalar broadcasts GCC 12 merges into 2-lane loads and rebuilds with 7.)
            DoubleLanes<2> xy;
            std::memcpy(&xy, xj, sizeof xy);
            r0 += (__builtin_shufflevector(xy, xy, 0, 0, 0, 0) - ox) * w;
            r1 += (__builtin_shufflevector(xy, xy, 1, 1, 1, 1) - oy) * w;
            r2 += (broadcast<4>(xj[2]) - oz) * w;
        } else { // 2-wide halves: a scalar subtraction, then the broadcast
            const double dx = xj[0] - origin.x(), dy = xj[1] - origin.y(), dz = xj[2] - origin.z();
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
    return sums<false, 3>(g, flat(x), [&](int j) { return particles.moment(j, q[j]); }).A;
}

Eigen::Matrix3d ShapeMatchingGroups::deformation(int g, const OrientedParticles& particles,
                                                 std::span<const Eigen::Vector3d> x,
                                                 std::span<const Eigen::Quaterniond> q) const {
    return moment(g, particles, x, q) * restMomentInverse_[g];
}

std::vector<Eigen::Matrix3d> ShapeMatchingGroups::deformations(const OrientedParticles& particles,
                                                               std::span<const Eigen::Vector3d> x,
                                                               std::span<const Eigen::Quaterniond> q,
                                                               SimdPath path) const {
    if (!simdPathAvailable(path))
        throw InputError("shape matching: deformations on the AVX2 path on a processor without AVX2");
    std::vector<Eigen::Matrix3d> D(static_cast<size_t>(size()));
    path == SimdPath::Avx2 ? deformationsAvx2(particles, x, q, D) : deformationsOn<false>(particles, x, q, D);
    return D;
}

template <bool wide>
SHATTER_LANES_INLINE void ShapeMatchingGroups::deformationsOn(const OrientedParticles& particles,
                                                              std::span<const Eigen::Vector3d> x,
                                                              std::span<const Eigen::Quaterniond> q,
                                                              std::span<Eigen::Matrix3d> D) const {
    std::vector<Eigen::Matrix3d> moments(static_cast<size_t>(particles.size()));
    for (int j = 0; j < particles.size(); ++j) moments[size_t(j)] = particles.moment(j, q[j]);
    for (int g = 0; g < size(); ++g)
        D[size_t(g)] = sums<wide, 3>(g, flat(x), [&](int j) -> const Eigen::Matrix3d& { return moments[size_t(j)]; }).A *
                       restMomentInverse_[g];
}

SHATTER_AVX2 void ShapeMatchingGroups::deformationsAvx2(const OrientedParticles& particles,
                                                        std::span<const Eigen::Vector3d> x,
                                                        std::span<const Eigen::Quaterniond> q,
                                                        std::span<Eigen::Matrix3d> D) const {
    deformationsOn<true>(particles, x, q, D);
}

Eigen::Quaterniond ShapeMatchingGroups::fitRotation(int g, const OrientedParticles& particles,
                                                    std::span<const Eigen::Vector3d> x,
                                                    std::span<const Eigen::Quaterniond> q, int rotationIterations) {
    rotation_[g] = extractRotation(moment(g, particles, x, q), rotation_[g], rotationIterations);
    return rotation_[g];
}

void ShapeMatchingGroups::refreshMoments(const OrientedParticles& particles, std::span<const Eigen::Quaterniond> q,
                                         SimdPath path) {
    if (!simdPathAvailable(path))
        throw InputError("shape matching: refreshMoments on the AVX2 path on a processor without AVX2");
    rotatedMoment_.resize(size_t(particles.size()));
    fixed_.resize(size_t(particles.size()));
    anyFixed_ = false;
    for (int j = 0; j < particles.size(); ++j) {
        fixed_[size_t(j)] = particles.fixed[j];
        anyFixed_ = anyFixed_ || particles.fixed[j];
    }
    if (path == SimdPath::Avx2) return refreshMomentsAvx2(particles, q);
    for (int j = 0; j < particles.size(); ++j) rotatedMoment_[size_t(j)] = particles.moment(j, q[j]);
}

SHATTER_AVX2 void ShapeMatchingGroups::refreshMomentsAvx2(const OrientedParticles& particles,
                                                          std::span<const Eigen::Quaterniond> q) {
    using Row = DoubleLanes<4>;
    const int n = particles.size();
    for (int first = 0; first < n; first += kRotationLanes) {
        int p[kRotationLanes];
        for (int l = 0; l < kRotationLanes; ++l) p[l] = std::min(first + l, n - 1); // past the end: idle, not written
        Row coefficients[4];
#pragma GCC unroll 4
        for (int l = 0; l < kRotationLanes; ++l) std::memcpy(&coefficients[l], q[p[l]].coeffs().data(), sizeof(Row));
        transpose(coefficients);
        Row m0[4], m1[4], m8;
        rotatedMoments(coefficients, p, particles, m0, m1, m8);
#pragma GCC unroll 4
        for (int l = 0; l < kRotationLanes; ++l)
            if (first + l < n) storeMoment(l, m0, m1, m8, rotatedMoment_[size_t(first + l)]);
    }
}

// Group g's projection, one batch at a time, compiled into each path's sweep (and into
// project()): always inlined, so that each copy is built for its instruction set.
[[gnu::always_inline]] inline void ShapeMatchingGroups::projectBatch(std::span<const int> groups,
                                                                     const OrientedParticles& particles, double* x,
                                                                     std::span<Eigen::Quaterniond> q,
                                                                     double stiffness, int rotationIterations,
                                                                     double newtonStop, SimdPath path) {
    using Row = DoubleLanes<4>;
    const int count = int(groups.size());
    // Each group's sums are set into its lane of the fits (extractRotations's bits), which
    // then run on all four lanes at once (unused lanes: a fit with nothing to fit).
    RotationLanes fits{RotationLanes::Unset{}};
    for (int l = count; l < kRotationLanes; ++l) fits.clear(l);
    Eigen::Vector3d centre[kRotationLanes];
    for (int l = 0; l < count; ++l) {
        const auto moment = [&](int j) -> const Eigen::Matrix3d& { return rotatedMoment_[size_t(j)]; };
        const Sums sum =
            path == SimdPath::Avx2 ? sums<true, 4>(groups[l], x, moment) : sums<false, 3>(groups[l], x, moment);
        fits.set(l, sum.A, rotation_[groups[l]]);
        centre[l] = sum.centre;
    }
    fitRotations(fits, count, rotationIterations, 1e-12, newtonStop, path);
    // The fits' rotation matrices on the lanes (toRotationMatrix's bits); for the AVX2 update,
    // each group's rows (below) are a transpose of them.
    Row r[9];
    rotationMatrices<4>(fits.w, fits.x, fits.y, fits.z, r);
    Row ra[4] = {r[0], r[3], r[7], Row{}}, rb[4] = {r[1], r[4], r[8], Row{}}, rc[4] = {r[2], r[5], r[6], Row{}};
    if (path == SimdPath::Avx2) {
        transpose(ra);
        transpose(rb);
        transpose(rc);
    }
    // A body with no fixed particle (most) skips the test per member.
    const bool anyFixed = anyFixed_;
    int centreParticle[kRotationLanes];
    LaneMask<4> turns = {};
    for (int l = 0; l < count; ++l) {
        const int g = groups[l];
        rotation_[g] = fits.answer(l);
        const int* const particle = members_.data() + offsets_[g];
        centreParticle[l] = *particle;
        turns[l] = !anyFixed || !fixed_[size_t(*particle)] ? -1 : 0;
        const int members = offsets_[g + 1] - offsets_[g];
        if (path == SimdPath::Portable) {
            // The same update in Eigen's 3-vectors, the same bits (Eigen's order, below): on
            // SSE2 the 4-lane rows went through the stack (x_j built from 3 loads), 35% slower.
            Eigen::Matrix3d R;
            for (int e = 0; e < 9; ++e) R(e / 3, e % 3) = r[e][l];
            for (int k = 0; k < members; ++k) {
                const int j = particle[k];
                if (anyFixed && fixed_[size_t(j)]) continue;
                Eigen::Map<Eigen::Vector3d> xj(x + 3 * std::ptrdiff_t(j));
                const Eigen::Vector3d offset = Eigen::Map<const Eigen::Vector3d>(restPoint_[size_t(j)].v) - restCentre_[g];
                xj += stiffness * (R * offset + centre[l] - xj);
            }
        } else {
            // x_j += k (R r̄_j + c − x_j) with x_j, R r̄_j and c as rows of 4 (the last lane
            // idle). R r̄_j in the order of Eigen's 3 × 3 product, whose bits the solver had: its
            // first two rows as (R₀₀ r̄_x + R₀₁ r̄_y) + R₀₂ r̄_z (a packet), the third as
            // R₂₀ r̄_x + (R₂₁ r̄_y + R₂₂ r̄_z), which is (R₂₁ r̄_y + R₂₂ r̄_z) + R₂₀ r̄_x: so with
            // r̄ permuted per lane (one instruction each) every lane is (a + b) + c, no blend.
            // Ra = (R₀₀, R₁₀, R₂₁, 0), Rb = (R₀₁, R₁₁, R₂₂, 0), Rc = (R₀₂, R₁₂, R₂₀, 0).
            const Row Ra = ra[l], Rb = rb[l], Rc = rc[l];
            const Row c{centre[l].x(), centre[l].y(), centre[l].z(), 0.0};
            const Row restCentre{restCentre_[g].x(), restCentre_[g].y(), restCentre_[g].z(), 0.0};
            for (int k = 0; k < members; ++k) {
                const int j = particle[k];
                if (anyFixed && fixed_[size_t(j)]) continue;
                double* const xj = x + 4 * std::ptrdiff_t(j);
                Row moved; // its last lane stays 0: so are those of goal and c
                std::memcpy(&moved, xj, sizeof moved);
                Row rest; // (r̄, 1): its last lane meets only the rows' zero lanes
                std::memcpy(&rest, restPoint_[size_t(j)].v, sizeof rest);
                rest -= restCentre;
                const Row goal = (Ra * __builtin_shufflevector(rest, rest, 0, 0, 1, 3) +
                                  Rb * __builtin_shufflevector(rest, rest, 1, 1, 2, 3)) +
                                 Rc * __builtin_shufflevector(rest, rest, 2, 2, 0, 3);
                moved += stiffness * (goal + c - moved);
                std::memcpy(xj, &moved, sizeof moved);
            }
        }
    }
    // Only the centre takes its group's rotation: turned toward it, its moment kept current.
    for (int l = count; l < kRotationLanes; ++l) centreParticle[l] = centreParticle[0]; // idle: read, not written
    turnCentres(fits, centreParticle, turns, stiffness, particles, q, rotatedMoment_.data());
}

void ShapeMatchingGroups::project(int g, const OrientedParticles& particles, std::span<Eigen::Vector3d> x,
                                  std::span<Eigen::Quaterniond> q, double stiffness, int rotationIterations,
                                  double newtonStop) {
    projectBatch({&g, 1}, particles, flat(x), q, stiffness, rotationIterations, newtonStop,
                 SimdPath::Portable);
}

void ShapeMatchingGroups::padPositions(std::span<const Eigen::Vector3d> x) {
    sweepPositions_.resize(x.size());
    for (size_t j = 0; j < x.size(); ++j) std::memcpy(sweepPositions_[j].v, x[j].data(), 3 * sizeof(double));
}

void ShapeMatchingGroups::unpadPositions(std::span<Eigen::Vector3d> x) const {
    for (size_t j = 0; j < x.size(); ++j) std::memcpy(x[j].data(), sweepPositions_[j].v, 3 * sizeof(double));
}

void ShapeMatchingGroups::projectAll(const OrientedParticles& particles, std::span<Eigen::Vector3d> x,
                                     std::span<Eigen::Quaterniond> q, double stiffness, int rotationIterations,
                                     double newtonStop, SimdPath path) {
    if (!simdPathAvailable(path))
        throw InputError("shape matching: projectAll on the AVX2 path on a processor without AVX2");
    if (path == SimdPath::Portable) return projectAllPortable(particles, x, q, stiffness, rotationIterations, newtonStop);
    padPositions(x);
    projectAllAvx2(particles, q, stiffness, rotationIterations, newtonStop);
    unpadPositions(x);
}

void ShapeMatchingGroups::projectAllInRun(const OrientedParticles& particles, std::span<Eigen::Vector3d> x,
                                          std::span<Eigen::Quaterniond> q, double stiffness, int rotationIterations,
                                          double newtonStop, SimdPath path, bool first, bool last,
                                          std::span<const int> touched, double omega) {
    const bool accelerated = omega > 0.0 && !(first && last);
    if (!accelerated && (path == SimdPath::Portable || (first && last)))
        return projectAll(particles, x, q, stiffness, rotationIterations, newtonStop, path);
    if (!simdPathAvailable(path))
        throw InputError("shape matching: projectAll on the AVX2 path on a processor without AVX2");
    if (first) {
        for (int j : touched)
            if (j < 0 || size_t(j) >= x.size())
                throw InputError("shape matching: projectAllInRun's touched particle " + std::to_string(j) +
                                 " is not one of the " + std::to_string(x.size()) + " positions");
        if (accelerated) sweepStart_.resize(x.size()), sweepDelta_.resize(x.size());
    } else if (accelerated ? sweepDelta_.size() != x.size()
                           : path == SimdPath::Avx2 && sweepPositions_.size() != x.size()) {
        // Between a run's sweeps x is current only at `touched` (AVX2), and an accelerated
        // sweep extrapolates the last one's motion: another x cannot continue the run.
        throw std::logic_error("shape matching: a later sweep of a run over positions of another size");
    }
    if (path == SimdPath::Portable) { // accelerated: the sweep on x itself
        keepSweepStart(x);
        projectAllPortable(particles, x, q, stiffness, rotationIterations, newtonStop);
        return accelerateSweep(x, omega, first);
    }
    // An accelerated run's start of a sweep is the last sweep's end (accelerateSweepAvx2 keeps
    // it) with the touched particles' moves: copied whole once a run (a copy per sweep was 1.8%
    // of the sheet bench's instructions, as callgrind counts rep movsb).
    if (first) {
        padPositions(x);
        if (accelerated) sweepStart_ = sweepPositions_;
    } else {
        for (int j : touched) {
            std::memcpy(sweepPositions_[size_t(j)].v, x[size_t(j)].data(), 3 * sizeof(double));
            if (accelerated) std::memcpy(sweepStart_[size_t(j)].v, x[size_t(j)].data(), 3 * sizeof(double));
        }
    }
    projectAllAvx2(particles, q, stiffness, rotationIterations, newtonStop);
    if (accelerated) accelerateSweepAvx2(omega, first);
    if (last) return unpadPositions(x);
    for (int j : touched) std::memcpy(x[size_t(j)].data(), sweepPositions_[size_t(j)].v, 3 * sizeof(double));
}

// accelerateSweep on the padded copy, a row of 4 at a time: the same operations lane by lane
// (the idle lanes stay 0: 0 − 0, ω 0 + (ω − 1) 0); it leaves sweepStart_ at the result, the
// next sweep's start. The scalar loop on the portable build cost 48 instructions a particle,
// 2.2% of the sheet bench's.
SHATTER_AVX2 void ShapeMatchingGroups::accelerateSweepAvx2(double omega, bool first) {
    using Row = DoubleLanes<4>;
    const Row w{omega, omega, omega, omega}, wLess1 = w - 1.0;
    for (size_t j = 0; j < sweepStart_.size(); ++j) {
        Row x, start, delta;
        std::memcpy(&x, sweepPositions_[j].v, sizeof x);
        std::memcpy(&start, sweepStart_[j].v, sizeof start);
        if (first) {
            delta = x - start;
        } else {
            std::memcpy(&delta, sweepDelta_[j].v, sizeof delta);
            delta = w * (x - start) + wLess1 * delta;
            x = start + delta;
            std::memcpy(sweepPositions_[j].v, &x, sizeof x);
        }
        std::memcpy(sweepDelta_[j].v, &delta, sizeof delta);
        std::memcpy(sweepStart_[j].v, &x, sizeof x); // the next sweep's start
    }
}

void ShapeMatchingGroups::keepSweepStart(std::span<const Eigen::Vector3d> x) {
    for (size_t j = 0; j < sweepStart_.size(); ++j) std::memcpy(sweepStart_[j].v, x[j].data(), 3 * sizeof(double));
}

// Element by element, the same operations on every path (no fused multiply-add on either):
// the same bits.
void ShapeMatchingGroups::accelerateSweep(std::span<Eigen::Vector3d> x, double omega, bool first) {
    for (size_t j = 0; j < sweepStart_.size(); ++j) {
        double* const xj = x[j].data();
        const double* const start = sweepStart_[j].v;
        double* const delta = sweepDelta_[j].v;
        for (int c = 0; c < 3; ++c) {
            const double moved = xj[c] - start[c];
            if (first) {
                delta[c] = moved;
                continue;
            }
            delta[c] = omega * moved + (omega - 1.0) * delta[c];
            xj[c] = start[c] + delta[c];
        }
    }
}

void ShapeMatchingGroups::projectAllPortable(const OrientedParticles& particles, std::span<Eigen::Vector3d> x,
                                             std::span<Eigen::Quaterniond> q, double stiffness,
                                             int rotationIterations, double newtonStop) {
    for (int b = 0; b < batches(); ++b)
        projectBatch(batch(b), particles, flat(x), q, stiffness, rotationIterations, newtonStop,
                     SimdPath::Portable);
}

SHATTER_AVX2 void ShapeMatchingGroups::projectAllAvx2(const OrientedParticles& particles,
                                                      std::span<Eigen::Quaterniond> q, double stiffness,
                                                      int rotationIterations, double newtonStop) {
    for (int b = 0; b < batches(); ++b)
        projectBatch(batch(b), particles, reinterpret_cast<double*>(sweepPositions_.data()), q, stiffness,
                     rotationIterations, newtonStop, SimdPath::Avx2);
}

} // namespace shatter::oriented
