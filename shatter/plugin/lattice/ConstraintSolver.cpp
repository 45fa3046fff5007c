#include <shatter/plugin/lattice/ConstraintSolver.h>

#include <shatter/plugin/common/InputError.h>
#include <shatter/plugin/common/SettingCheck.h>
#include <shatter/plugin/lattice/ConjugateGradientStep.h>
#include <shatter/plugin/lattice/RowProof.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <numeric>

namespace shatter::lattice {

namespace {

// Links around the residual that the first region takes (doubled each time it is not enough):
// a link's force falls off by about 3 per link away from a load, so 4 links take it to ~1%.
constexpr int kFirstHops = 4;

// Iterations between a region's checks whether its breaks look decided: the check reads every
// row of the region once, a fraction of one product.
constexpr int kDecideEvery = 4;
// Failed "breaks decided" proofs before a region's CG goes on to its tolerance.
constexpr int kDecideTries = 3;
// Particles whose forces keptRightHandSide compares in one memcmp before it looks at each.
constexpr size_t kComparedRun = 64;
// A region's reach in links stops doubling here (no overflow; a region this wide is every row).
constexpr int kMostHops = 1 << 20;

// How far λ is from the nearer end of the break range (lower, upper), on either side of it.
double breakDistance(double lambda, double lower, double upper) {
    return std::min(std::abs(lambda - lower), std::abs(upper - lambda));
}

// Whether λ lies beyond the break range (lower, upper). Always inlined: `proven` calls it in
// its pass over every row, where an out-of-line call cost 40% more.
[[gnu::always_inline]] inline bool beyondBreak(const SafeRange& safe, size_t row, double lambda) {
    return lambda < safe.breakLower[row] || lambda > safe.breakUpper[row];
}

// y = J M⁻¹ Jᵀ x over rows (a, b, normal) between particles of the given inverse masses:
// Jᵀ x gives the force on each particle; M⁻¹ turns it into an acceleration; J reads back each
// link's relative acceleration along its normal (left in `scratch`). `padded` is the AVX2
// path's room for kBlockStride doubles a particle.
void multiplyRows(const std::vector<int>& a, const std::vector<int>& b, const std::vector<Eigen::Vector3d>& normal,
                  const std::vector<double>& inverseMass, const Eigen::VectorXd& x, Eigen::VectorXd& y,
                  std::vector<Eigen::Vector3d>& scratch, std::vector<double>& padded) {
    const size_t rows = a.size(), particles = inverseMass.size();
    scratch.resize(particles);
    padded.resize(size_t(kBlockStride) * particles);
    y.resize(Eigen::Index(rows));
    IndexedRows m;
    m.a = a.data(), m.b = b.data(), m.rows = Eigen::Index(rows);
    m.normal = rows ? normal.data()->data() : nullptr;
    m.inverseMass = inverseMass.data(), m.particles = Eigen::Index(particles), m.sums = padded.data();
    multiplyIndexedRows(m, x.data(), y.data(), particles ? scratch.data()->data() : nullptr);
}

} // namespace

ConstraintSystem::ConstraintSystem(const Lattice& lattice, std::vector<int> particles, std::vector<int> links)
    : particles_(std::move(particles)), joinedAtBuild_(lattice.joinedCount()) {
    // Local index by binary search in the ascending list: no hash map of a 50,000-tet piece.
    auto local = [&](int particle) {
        const auto it = std::lower_bound(particles_.begin(), particles_.end(), particle);
        return it != particles_.end() && *it == particle ? int(it - particles_.begin()) : -1;
    };
    inverseMass_.reserve(particles_.size());
    for (int p : particles_) inverseMass_.push_back(lattice.inverseMass(p));
    for (int k : links) {
        const Link& l = lattice.links()[k];
        if (l.broken) continue;
        const int a = local(l.a), b = local(l.b);
        if (a < 0 || b < 0) continue;
        if (inverseMass_[a] == 0.0 && inverseMass_[b] == 0.0) continue;
        ascending_ = ascending_ && (links_.empty() || links_.back() < k);
        appendRow(lattice, k, a, b);
    }
    indexRowsByParticle();
    scratch_.resize(particles_.size());
}

void ConstraintSystem::appendRow(const Lattice& lattice, int link, int a, int b) {
    links_.push_back(link);
    rowA_.push_back(a);
    rowB_.push_back(b);
    normal_.emplace_back();
    length_.push_back(0.0);
    diagonal_.push_back(0.0);
    rootDiagonal_.push_back(0.0);
    setRow(links_.size() - 1, lattice, link, a, b);
}

void ConstraintSystem::setRow(size_t row, const Lattice& lattice, int link, int a, int b) {
    const Link& l = lattice.links()[link];
    links_[row] = link;
    rowA_[row] = a;
    rowB_[row] = b;
    normal_[row] = l.normal;
    length_[row] = l.length;
    diagonal_[row] = l.normal.squaredNorm() * (inverseMass_[size_t(a)] + inverseMass_[size_t(b)]);
    rootDiagonal_[row] = std::sqrt(diagonal_[row]);
}

void ConstraintSystem::moveRow(size_t from, size_t to, Eigen::VectorXd& lambda) {
    links_[to] = links_[from];
    rowA_[to] = rowA_[from];
    rowB_[to] = rowB_[from];
    normal_[to] = normal_[from];
    length_[to] = length_[from];
    diagonal_[to] = diagonal_[from];
    rootDiagonal_[to] = rootDiagonal_[from];
    lambda[Eigen::Index(to)] = lambda[Eigen::Index(from)];
}

void ConstraintSystem::resizeRows(size_t count, Eigen::VectorXd& lambda) {
    for (auto* v : {&links_, &rowA_, &rowB_}) v->resize(count);
    normal_.resize(count);
    length_.resize(count);
    diagonal_.resize(count);
    rootDiagonal_.resize(count);
    lambda.conservativeResize(Eigen::Index(count)); // keeps the first values
}

void ConstraintSystem::indexRowsByParticle() {
    rowStart_.assign(particles_.size() + 1, 0);
    for (int k = 0; k < rowCount(); ++k) ++rowStart_[rowA_[k] + 1], ++rowStart_[rowB_[k] + 1];
    for (size_t i = 0; i < particles_.size(); ++i) rowStart_[i + 1] += rowStart_[i];
    rowsOf_.resize(size_t(rowStart_.back()));
    std::vector<int> filled(rowStart_.begin(), rowStart_.end() - 1);
    for (int k = 0; k < rowCount(); ++k) rowsOf_[size_t(filled[rowA_[k]]++)] = k, rowsOf_[size_t(filled[rowB_[k]]++)] = k;
}

bool ConstraintSystem::canRestrictTo(const Lattice& lattice, const std::vector<int>& particles) const {
    return (lattice.joinedCount() == joinedAtBuild_ || ascending_) &&
           std::includes(particles_.begin(), particles_.end(), particles.begin(), particles.end());
}

void ConstraintSystem::addJoinedRows(const Lattice& lattice, Eigen::VectorXd& lambda) {
    // Local index by binary search, as the constructor finds it.
    auto local = [&](int particle) {
        const auto it = std::lower_bound(particles_.begin(), particles_.end(), particle);
        return it != particles_.end() && *it == particle ? int(it - particles_.begin()) : -1;
    };
    std::vector<int> joined(lattice.joinedSince(joinedAtBuild_).begin(), lattice.joinedSince(joinedAtBuild_).end());
    std::sort(joined.begin(), joined.end());
    joined.erase(std::unique(joined.begin(), joined.end()), joined.end()); // a link joined twice
    // The rows a fresh build would add, in link order (the constructor's tests).
    std::vector<int> added;
    for (int k : joined) {
        const Link& l = lattice.links()[k];
        const int a = local(l.a), b = local(l.b);
        // (A link joined again before its broken row was dropped has a row.)
        if (lattice.isBroken(k) || a < 0 || b < 0 || (inverseMass_[size_t(a)] == 0.0 && inverseMass_[size_t(b)] == 0.0) ||
            std::binary_search(links_.begin(), links_.end(), k))
            continue;
        added.push_back(k);
    }
    joinedAtBuild_ = lattice.joinedCount();
    if (added.empty()) return;
    // Merged in from the back, in place: every row array grows by the new rows and each old row
    // moves up by the number of new rows after it, so only the rows from the first new one on
    // are moved, once (a permutation of all seven arrays copied each ~100,000 rows).
    const size_t before = links_.size(), after = before + added.size();
    resizeRows(after, lambda);
    size_t from = before, to = after;
    for (size_t j = added.size(); j-- > 0;) {
        const int k = added[j];
        while (from > 0 && links_[from - 1] > k) moveRow(--from, --to, lambda);
        --to;
        const Link& l = lattice.links()[k];
        setRow(to, lattice, k, local(l.a), local(l.b));
        lambda[Eigen::Index(to)] = 0.0; // λ = 0 on the new rows, as the rebuild's merge walk gave them
    }
    rhs_.b.resize(0); // rows added: b is formed anew
}

void ConstraintSystem::restrictTo(const Lattice& lattice, const std::vector<int>& particles, Eigen::VectorXd& lambda) {
    // Refused before anything changes, so a caller that catches the error keeps a whole system.
    if (lattice.joinedCount() != joinedAtBuild_ && !ascending_)
        throw InputError("ConstraintSystem::restrictTo: links were joined and the rows are not in link order "
                         "(canRestrictTo says which systems take them)");
    // New local index of each old local particle (-1: left), by a merge walk of both lists.
    std::vector<int> number(particles_.size(), -1);
    size_t found = 0;
    for (size_t i = 0; i < particles_.size() && found < particles.size(); ++i)
        if (particles_[i] == particles[found]) number[i] = int(found++);
    // A particle the system does not hold would stall the walk and drop every row after it.
    if (found != particles.size())
        throw InputError("ConstraintSystem::restrictTo: particle " + std::to_string(particles[found]) +
                                    " is not in the system (canRestrictTo says which lists it takes)");
    // b keeps its rows' values (each row's is its own); renumbered particles drop it.
    const bool keepRhs = rhs_.b.size() == rowCount();
    // Compacted through pointers held in locals: through the vectors, every store made the
    // compiler load each array's pointer again (about 49 instructions a row).
    int* const links = links_.data();
    int *const ends0 = rowA_.data(), *const ends1 = rowB_.data();
    Eigen::Vector3d* const normals = normal_.data();
    double *const lengths = length_.data(), *const diagonals = diagonal_.data(), *const roots = rootDiagonal_.data();
    double* const lambdas = lambda.data();
    double* const rhs = keepRhs ? rhs_.b.data() : nullptr;
    const int* const numbers = number.data();
    size_t kept = 0;
    for (size_t k = 0, rows = size_t(rowCount()); k < rows; ++k) {
        const int a = numbers[ends0[k]], b = numbers[ends1[k]];
        if (a < 0 || b < 0 || lattice.isBroken(links[k])) continue;
        links[kept] = links[k];
        ends0[kept] = a;
        ends1[kept] = b;
        normals[kept] = normals[k];
        lengths[kept] = lengths[k];
        lambdas[kept] = lambdas[k];
        diagonals[kept] = diagonals[k];
        roots[kept] = roots[k];
        if (rhs) rhs[kept] = rhs[k];
        ++kept;
    }
    resizeRows(kept, lambda);
    product_.lambda.resize(0); // rows dropped: the kept product is of another system
    if (keepRhs) rhs_.b.conservativeResize(Eigen::Index(kept));
    if (particles.size() != particles_.size()) {
        rhs_.forces.resize(0);
        for (size_t i = 0; i < particles_.size(); ++i)
            if (number[i] >= 0) inverseMass_[size_t(number[i])] = inverseMass_[i];
        particles_ = particles;
        inverseMass_.resize(particles_.size());
        scratch_.resize(particles_.size());
    }
    if (lattice.joinedCount() != joinedAtBuild_) addJoinedRows(lattice, lambda);
    // (Filtering the old index in place instead, through an old-row -> new-row table, took
    // 39 M instructions in the Spot's first 13 frames against the rebuild's 44 M, and the
    // table's writes cost more than the difference.)
    indexRowsByParticle();
}

void ConstraintSystem::multiply(const Eigen::VectorXd& x, Eigen::VectorXd& y) const {
    multiplyRows(rowA_, rowB_, normal_, inverseMass_, x, y, scratch_, paddedSums_);
}

const Eigen::VectorXd& ConstraintSystem::productOf(const Eigen::VectorXd& x) const {
    Product& kept = product_;
    // Compared bit for bit: -0 and +0 give products whose zeros differ in sign.
    const size_t bytes = size_t(x.size()) * sizeof(double);
    if (kept.lambda.size() == x.size() && std::memcmp(kept.lambda.data(), x.data(), bytes) == 0) return kept.rows;
    multiplyRows(rowA_, rowB_, normal_, inverseMass_, x, kept.rows, kept.acceleration, paddedSums_);
    kept.lambda = x;
    return kept.rows;
}

void ConstraintSystem::updateProduct(const Region& region, const Eigen::VectorXd& x) const {
    Product& kept = product_;
    if (kept.lambda.size() != rowCount()) return; // nothing kept
    if (region.rows.size() == size_t(rowCount())) { // every row: the multiply is cheaper
        kept.lambda.resize(0);
        return;
    }
    for (int k : region.rows) kept.lambda[k] = x[k];
    for (int p : region.particles) {
        // multiplyRows: from zero, + n_k x_k where the particle is a row's first end, - where
        // it is the second, in ascending row order, then × 1/m.
        Eigen::Vector3d sum = Eigen::Vector3d::Zero();
        for (int i = rowStart_[p]; i < rowStart_[p + 1]; ++i) {
            const int k = rowsOf_[size_t(i)];
            const Eigen::Vector3d f = normal_[size_t(k)] * x[k];
            if (rowA_[size_t(k)] == p) sum += f;
            else sum -= f;
        }
        sum *= inverseMass_[size_t(p)];
        kept.acceleration[size_t(p)] = sum;
    }
    for (int p : region.particles)
        for (int i = rowStart_[p]; i < rowStart_[p + 1]; ++i) {
            const int k = rowsOf_[size_t(i)];
            kept.rows[k] = normal_[size_t(k)].dot(kept.acceleration[size_t(rowA_[size_t(k)])] -
                                                  kept.acceleration[size_t(rowB_[size_t(k)])]);
        }
}

Eigen::VectorXd ConstraintSystem::jacobianTimes(const Eigen::VectorXd& v) const {
    Eigen::VectorXd out(rowCount());
    for (int k = 0; k < rowCount(); ++k)
        out[k] = normal_[k].dot(v.segment<3>(3 * rowA_[k]) - v.segment<3>(3 * rowB_[k]));
    return out;
}

Eigen::VectorXd ConstraintSystem::constraintForces(const Eigen::VectorXd& lambda) const {
    Eigen::VectorXd f = Eigen::VectorXd::Zero(3 * particleCount());
    for (int k = 0; k < rowCount(); ++k) {
        f.segment<3>(3 * rowA_[k]) += normal_[k] * lambda[k];
        f.segment<3>(3 * rowB_[k]) -= normal_[k] * lambda[k];
    }
    return f;
}

double ConstraintSystem::rightHandSideRow(size_t k, const Eigen::VectorXd& forces, const Eigen::Vector3d& omega) const {
    const size_t a = size_t(rowA_[k]), b = size_t(rowB_[k]);
    const Eigen::Vector3d accA = inverseMass_[a] * forces.segment<3>(Eigen::Index(3 * a));
    const Eigen::Vector3d accB = inverseMass_[b] * forces.segment<3>(Eigen::Index(3 * b));
    // J̇q̇ for a distance constraint is |v_rel|²/d - (n·v_rel)²/d; in a rigid rotation
    // v_rel = ω × d is normal to d, so only |ω × d|²/d is left.
    const double centripetal = omega.cross(normal_[k]).squaredNorm() * length_[k];
    return -centripetal - normal_[k].dot(accA - accB);
}

Eigen::VectorXd ConstraintSystem::rightHandSide(const Eigen::VectorXd& forces, const Eigen::Vector3d& omega) const {
    Eigen::VectorXd b(rowCount());
    for (int k = 0; k < rowCount(); ++k) b[k] = rightHandSideRow(size_t(k), forces, omega);
    return b;
}

const Eigen::VectorXd& ConstraintSystem::keptRightHandSide(const Eigen::VectorXd& forces,
                                                           const Eigen::Vector3d& omega) const {
    Rhs& kept = rhs_;
    auto same = [](const double* x, const double* y, size_t count) { return std::memcmp(x, y, count * sizeof(double)) == 0; };
    if (kept.forces.size() != forces.size() || kept.b.size() != rowCount() || !same(kept.omega.data(), omega.data(), 3)) {
        kept.b = rightHandSide(forces, omega);
        kept.forces = forces;
        kept.omega = omega;
        return kept.b;
    }
    // A run of particles at a time first (one memcmp): most runs of a resting piece are equal.
    for (size_t first = 0, count = particles_.size(); first < count; first += kComparedRun) {
        const size_t end = std::min(count, first + kComparedRun);
        if (same(forces.data() + 3 * first, kept.forces.data() + 3 * first, 3 * (end - first))) continue;
        for (size_t p = first; p < end; ++p) {
            const double* now = forces.data() + 3 * p;
            double* was = kept.forces.data() + 3 * p;
            if (same(now, was, 3)) continue;
            std::memcpy(was, now, 3 * sizeof(double));
            for (int i = rowStart_[p]; i < rowStart_[p + 1]; ++i) {
                const size_t k = size_t(rowsOf_[size_t(i)]);
                kept.b[Eigen::Index(k)] = rightHandSideRow(k, forces, omega);
            }
        }
    }
    return kept.b;
}

void ConstraintSolverSettings::check(const std::string& body) const {
    requireSetting(tolerance > 0.0 && tolerance < 1.0, body, "solver tolerance", "in (0, 1)", tolerance);
    requireAtLeast(body, "solver max iterations", maxIterations, 1);
}

ConstraintSystem::Region ConstraintSystem::everyRow() const {
    Region all;
    all.rows.resize(size_t(rowCount()));
    std::iota(all.rows.begin(), all.rows.end(), 0);
    all.particles.resize(particles_.size());
    std::iota(all.particles.begin(), all.particles.end(), 0);
    return all;
}

ConstraintSystem::Region ConstraintSystem::regionAround(const Eigen::VectorXd& residual, double floor,
                                                        double scaledFloor, int hops, Taken& taken) const {
    std::vector<int> frontier;
    auto take = [&](int particle, std::vector<int>& into) {
        if (inverseMass_[particle] == 0.0 || taken.flag[particle]) return; // a fixed particle couples no rows
        taken.flag[particle] = 1;
        taken.list.push_back(particle);
        into.push_back(particle);
    };
    // The residual's data and the row count held in locals: `take` appends to vectors, after
    // which the compiler loaded both again on every row of this scan (11 instructions a row).
    const double* const residuals = residual.data();
    for (size_t k = 0, rows = size_t(rowCount()); k < rows; ++k) {
        const double size = std::abs(residuals[k]);
        if (size > floor && size > scaledFloor * rootDiagonal_[k]) take(rowA_[k], frontier), take(rowB_[k], frontier);
    }
    for (int hop = 0; hop < hops && !frontier.empty(); ++hop) {
        std::vector<int> next;
        for (int p : frontier)
            for (int i = rowStart_[p]; i < rowStart_[p + 1]; ++i) {
                const int k = rowsOf_[size_t(i)];
                take(rowA_[k] == p ? rowB_[k] : rowA_[k], next);
            }
        frontier = std::move(next);
    }
    // Every row of a taken particle, and the particles at their ends, particles ascending (the
    // order CG's sums see the rows in), from the list of those taken instead of a scan of all.
    // The list's head is sorted by the last round: only this round's particles are sorted and
    // merged in, or, when they are many (over 1/16 of the particles), the list is read off the
    // flags in one pass. Sorting the whole list each round was 20 M instructions of the Spot's
    // frame 13 (55,411 particles).
    if (16 * (taken.list.size() - taken.sorted) > particles_.size()) {
        taken.list.clear();
        for (size_t p = 0; p < particles_.size(); ++p)
            if (taken.flag[p]) taken.list.push_back(int(p));
    } else {
        const auto head = taken.list.begin() + std::ptrdiff_t(taken.sorted);
        std::sort(head, taken.list.end());
        std::inplace_merge(taken.list.begin(), head, taken.list.end());
    }
    taken.sorted = taken.list.size();
    Region region;
    std::vector<char>&rowTaken = marks_.rows, &particleTaken = marks_.particles;
    for (int p : taken.list)
        for (int i = rowStart_[p]; i < rowStart_[p + 1]; ++i) {
            const int k = rowsOf_[size_t(i)];
            if (rowTaken[k]) continue;
            rowTaken[k] = 1;
            region.rows.push_back(k);
            for (int end : {rowA_[k], rowB_[k]})
                if (!particleTaken[end]) particleTaken[end] = 1, region.particles.push_back(end);
        }
    // The free particles at the region's edge (not taken) couple it to the boundary rows.
    for (int p : region.particles) {
        if (taken.flag[p] || inverseMass_[p] == 0.0) continue;
        for (int i = rowStart_[p]; i < rowStart_[p + 1]; ++i) {
            const int k = rowsOf_[size_t(i)];
            if (!rowTaken[k]) rowTaken[k] = 1, region.boundary.push_back(k);
        }
    }
    for (const auto* rows : {&region.rows, &region.boundary})
        for (int k : *rows) rowTaken[size_t(k)] = 0;
    for (int p : region.particles) particleTaken[size_t(p)] = 0;
    return region;
}

void ConstraintSystem::Marks::fit(size_t rowCount, size_t particleCount) {
    // Entries are cleared after each use, so a buffer of the right size is all zeros already.
    if (rows.size() != rowCount) rows.assign(rowCount, 0);
    if (particles.size() != particleCount) particles.assign(particleCount, 0);
}

void ConstraintSystem::Taken::clear(size_t particleCount) {
    for (int p : list) flag[size_t(p)] = 0;
    list.clear();
    sorted = 0;
    if (flag.size() != particleCount) flag.assign(particleCount, 0);
}

namespace {
// v grown to at least n entries, never shrunk: the block's buffers are rewritten by every
// copy(), and resizing them down and up again as a solve's regions shrink and grow zero-filled
// them each time (Spot frames 1-13: 17 M instructions of memset, 30 M once the ends were
// pointers, 8.5 M growing only).
template <class T>
void growTo(std::vector<T>& v, size_t n) {
    if (v.size() < n) v.resize(n);
}
} // namespace

void ConstraintSystem::Block::copy(const ConstraintSystem& system, const Region& region) {
    // (Room for the sums after up to 7 doubles that bring them to a line; malloc aligns to 16.
    // A 32-byte sum at 16-byte alignment straddled two cache lines every other particle.)
    growTo(scratch, size_t(kBlockStride) * region.particles.size() + 7);
    constexpr size_t kLine = 64;
    const size_t misaligned = reinterpret_cast<std::uintptr_t>(scratch.data()) % kLine;
    sumsStart = scratch.data() + (misaligned ? (kLine - misaligned) / sizeof(double) : 0);
    // Block number and sum of each region particle; the region lists every particle its rows
    // touch. Only the region's entries of `number` and `sumOf` are written and read, so they are
    // never cleared. (A row's ends read from `sumOf`, not formed from `number`: 2 instructions
    // fewer an end, and a particle has several rows.)
    number.resize(system.particles_.size());
    sumOf.resize(system.particles_.size());
    inverseMass.resize(region.particles.size());
    // (Pointers in locals: through the members, each store made the compiler load them again.)
    int* const numberOut = number.data();
    double** const sumOfOut = sumOf.data();
    double* const massOut = inverseMass.data();
    const double* const massIn = system.inverseMass_.data();
    double* const sums = sumsStart;
    for (size_t i = 0; i < region.particles.size(); ++i) {
        const size_t p = size_t(region.particles[i]);
        numberOut[p] = int(i);
        sumOfOut[p] = sums + kBlockStride * i;
        massOut[i] = massIn[p];
    }
    rowCount = region.rows.size();
    growTo(ends, 2 * rowCount);
    growTo(normal, 3 * rowCount + 1);
    double** const endsOut = ends.data();
    double* const* const sumOut = sumOf.data();
    double* const normalOut = normal.data();
    for (size_t j = 0; j < region.rows.size(); ++j) {
        const size_t k = size_t(region.rows[j]);
        endsOut[2 * j] = sumOut[size_t(system.rowA_[k])];
        endsOut[2 * j + 1] = sumOut[size_t(system.rowB_[k])];
        const Eigen::Vector3d& n = system.normal_[k];
        double* const to = normalOut + 3 * j;
        to[0] = n[0], to[1] = n[1], to[2] = n[2];
    }
    normal[3 * rowCount] = 0.0;
    // `number` is stale outside the region: a particle is in it when its entry points back to it.
    auto inBlock = [&](int particle) {
        const int i = number[size_t(particle)];
        return i >= 0 && size_t(i) < region.particles.size() && region.particles[size_t(i)] == particle ? i : -1;
    };
    edgeA.clear();
    edgeB.clear();
    for (int k : region.boundary) {
        edgeA.push_back(inBlock(system.rowA_[size_t(k)]));
        edgeB.push_back(inBlock(system.rowB_[size_t(k)]));
    }
}

BlockRows ConstraintSystem::Block::rows() const {
    BlockRows rows;
    rows.ends = ends.data();
    rows.normal = normal.data();
    rows.rows = Eigen::Index(rowCount);
    rows.inverseMass = inverseMass.data();
    rows.sums = sums();
    rows.particles = Eigen::Index(inverseMass.size());
    return rows;
}

void ConstraintSystem::Block::multiply(const Eigen::VectorXd& x, Eigen::VectorXd& y) const {
    y.resize(Eigen::Index(rowCount));
    multiplyBlock(rows(), x.data(), y.data());
}

ConstraintSystem::Outside ConstraintSystem::outsideOf(const Region& region, const Eigen::VectorXd& r,
                                                      const Eigen::VectorXd& x, const SafeRange& safe) const {
    // The system's row marks (all zero between uses; a region that is not every row comes
    // from regionAround, which fitted them), cleared again below.
    std::vector<char>& touched = marks_.rows;
    for (const auto* rows : {&region.rows, &region.boundary})
        for (int k : *rows) touched[size_t(k)] = 1;
    // The rows not marked, a packet at a time (RowProof.h): the plain loop's values.
    const OutsideProof sums = outsideProof(size_t(rowCount()), touched.data(), r.data(), x.data(), diagonal_.data(),
                                           rootDiagonal_.data(), safe.breakLower.data(), safe.breakUpper.data());
    const Outside out{sums.scaled, sums.squared, sums.room, sums.beyond};
    for (const auto* rows : {&region.rows, &region.boundary})
        for (int k : *rows) touched[size_t(k)] = 0;
    return out;
}

ConstraintSystem::Stop ConstraintSystem::solveRegion(const Region& region, const Eigen::VectorXd& residual,
                                                     double goal, double safeGoal, Decide& decide,
                                                     double bNorm, Eigen::VectorXd& lambda,
                                                     const ConstraintSolverSettings& s, SolveResult& result) const {
    const Eigen::Index n = Eigen::Index(region.rows.size());
    result.rowsSolved = std::max(result.rowsSolved, int(n));
    // Jacobi preconditioning: A_kk = |n_k|² (1/m_a + 1/m_b) = 1/m_a + 1/m_b, which varies with
    // the masses of a link's two tets (and halves next to a fixed one).
    block_.copy(*this, region);
    const Block& block = block_;
    const BlockRows blockRows = block.rows();
    Eigen::VectorXd inverseDiagonal(n), r(n), x(n);
    for (Eigen::Index j = 0; j < n; ++j) {
        const int k = region.rows[size_t(j)];
        inverseDiagonal[j] = block.inverseDiagonal(size_t(j));
        r[j] = residual[k];
        x[j] = lambda[k];
    }
    Eigen::VectorXd z = inverseDiagonal.cwiseProduct(r), p = z, ap(n);
    double rz = r.dot(z), rr = r.squaredNorm();
    // rz = r_Rᵀ D⁻¹ r_R: the squared Jacobi-scaled residual of the region.
    const SafeRange* safe = decide.safe;
    const Eigen::VectorXd start = x, startResidual = r;
    // With a break range: the region's √(1/d_j) and break range, contiguous for looksDecided's
    // pass every few iterations (through region.rows, its reads of the whole system's ranges
    // and a division a row were over half of solveRegion's own instructions on the wall).
    Eigen::VectorXd rootInverseDiagonal, breakLower, breakUpper;
    if (safe) {
        rootInverseDiagonal = inverseDiagonal.cwiseSqrt();
        breakLower.resize(n), breakUpper.resize(n);
        for (Eigen::Index j = 0; j < n; ++j) {
            const size_t k = size_t(region.rows[size_t(j)]);
            breakLower[j] = safe->breakLower[k];
            breakUpper[j] = safe->breakUpper[k];
        }
    }
    // Whether the rows at λ + x look decided by CG's own residual, the rest's part and the
    // boundary's at the last confirmation (solving the region moves residual onto its boundary):
    // each region row's distance to its break range's nearer end, × √d_k, beyond the reach with
    // a margin, and some row beyond its range. Most checks fail at an early row.
    double margin = 2.0, boundaryScaled = 0.0;
    int failures = 0;
    // The rows outside the region and its boundary keep the λ and residual they had before it
    // (their entries of `lambda` and `residual` are not written until it ends), so their part is
    // summed once, when the region's rows first look decided without it (most regions never do).
    Outside outside;
    bool outsideKnown = n == rowCount();
    auto looksDecided = [&] {
        const double reach = margin * std::sqrt(rz + outside.scaled + boundaryScaled) / safe->eigenvalueBound;
        if (outsideKnown && !(outside.room > reach)) return false;
        bool beyond = outside.beyond;
        if (!rowsLookDecided(n, x.data(), breakLower.data(), breakUpper.data(), rootInverseDiagonal.data(), reach, beyond))
            return false;
        return beyond || !outsideKnown;
    };
    // The proof on the whole residual (SafeRange; the same sums as `proven`): the region's and
    // its boundary's residuals formed again from the change of λ, r − A (x − start), the other
    // rows' parts from `outside`. One product over the region.
    Eigen::VectorXd change, changed;
    auto confirmed = [&] {
        change = x - start;
        block.multiply(change, changed); // leaves M⁻¹ Jᵀ (x − start) per block particle in block.sums()
        changed = startResidual - changed;
        double scaled = outside.scaled, squared = outside.squared;
        for (Eigen::Index j = 0; j < n; ++j) {
            scaled += changed[j] * changed[j] / diagonal_[size_t(region.rows[size_t(j)])];
            squared += changed[j] * changed[j];
        }
        auto acceleration = [&](int end) { return end < 0 ? Eigen::Vector3d::Zero().eval() : block.acceleration(end); };
        boundaryScaled = 0.0;
        for (size_t i = 0; i < region.boundary.size(); ++i) {
            const size_t k = size_t(region.boundary[i]);
            const double edge =
                residual[Eigen::Index(k)] - normal_[k].dot(acceleration(block.edgeA[i]) - acceleration(block.edgeB[i]));
            boundaryScaled += edge * edge / diagonal_[k];
            squared += edge * edge;
        }
        scaled += boundaryScaled;
        // The 1% covers the rounding of these sums, as in `proven`; NaN proves nothing.
        const double reach = 1.01 * std::sqrt(scaled) / safe->eigenvalueBound;
        if (!(outside.room > reach)) return false;
        bool beyond = outside.beyond;
        auto decided = [&](size_t k, double value) {
            beyond = beyond || beyondBreak(*safe, k, value);
            return decidedRow(*safe, k, value, reach);
        };
        for (Eigen::Index j = 0; j < n; ++j)
            if (!decided(size_t(region.rows[size_t(j)]), x[j])) return false;
        for (int k : region.boundary)
            if (!decided(size_t(k), lambda[k])) return false;
        decide.residual = std::sqrt(squared);
        return beyond;
    };
    Stop stop = Stop::Tolerance;
    // p = z + βp is formed by the next product (multiplyDirection), from this β and z; the first
    // p is z itself.
    double beta = 0.0;
    bool firstDirection = true;
    while (std::sqrt(rr) > goal && result.iterations < s.maxIterations) {
        if (safeGoal > 0.0 && std::sqrt(rz) <= safeGoal) {
            stop = Stop::Safe;
            break;
        }
        const double pap = multiplyDirection(blockRows, firstDirection ? nullptr : z.data(), beta, p.data(), ap.data());
        firstDirection = false;
        if (!(pap > 0.0)) break; // p in the null space: nothing left that the matrix can reach
        const double alpha = rz / pap;
        const StepSums sums = conjugateGradientStep(alpha, p, ap, inverseDiagonal, x, r, z);
        rr = sums.residual;
        ++result.iterations;
        if (s.onIteration) {
            for (Eigen::Index j = 0; j < n; ++j) lambda[region.rows[size_t(j)]] = x[j];
            s.onIteration(result.iterations, lambda, std::sqrt(rr) / bNorm);
        }
        const double rzNew = sums.preconditioned;
        beta = rzNew / rz;
        rz = rzNew;
        if (safe && failures < kDecideTries && result.iterations % kDecideEvery == 0 && looksDecided() &&
            (outsideKnown || (outside = outsideOf(region, residual, lambda, *safe), outsideKnown = true, looksDecided()))) {
            if (confirmed()) {
                stop = Stop::BreaksDecided;
                break;
            }
            // Not proven: checked again with a larger margin (most are decided a few iterations
            // later), a few times at most: below the residual CG can reach in floating point
            // its recurrence keeps falling while the true residual does not.
            margin *= 4.0;
            ++failures;
        }
    }
    for (Eigen::Index j = 0; j < n; ++j) lambda[region.rows[size_t(j)]] = x[j];
    return stop;
}

bool ConstraintSystem::decidedRow(const SafeRange& safe, size_t row, double lambda, double reach) const {
    return breakDistance(lambda, safe.breakLower[row], safe.breakUpper[row]) * rootDiagonal_[row] > reach;
}

ConstraintSystem::Stop ConstraintSystem::proven(const Eigen::VectorXd& r, const Eigen::VectorXd& x,
                                                const SafeRange& safe, double* goal) const {
    const RowProof sums = rowProof(size_t(rowCount()), r.data(), x.data(), diagonal_.data(), rootDiagonal_.data(), safe);
    const double scaled = sums.scaled, room = sums.room;
    const bool beyond = sums.beyond;
    // Proven when ‖D^-½ r‖/μ < slack_k √d_k on every row (SafeRange). The 1% covers the
    // rounding of these sums; NaN proves nothing. The proof is up to the rounding of r itself
    // (r = b − Ax in floating point is off by about u(|b| + |A||x|) per row, absolute): the
    // stop fires at residuals far above that (about 1e-14 of |b|), where it is negligible.
    const double reach = 1.01 * std::sqrt(scaled) / safe.eigenvalueBound;
    if (goal) *goal = room > 0.0 ? 0.5 * room * safe.eigenvalueBound : 0.0;
    if (reach < room) return Stop::Safe;
    if (!beyond) return Stop::Tolerance;
    // Decided when every row's distance to the break range's nearer end, × √d_k, exceeds reach.
    for (int k = 0; k < rowCount(); ++k)
        if (!decidedRow(safe, size_t(k), x[k], reach)) return Stop::Tolerance;
    return Stop::BreaksDecided;
}

SolveResult ConstraintSystem::solve(const Eigen::VectorXd& b, Eigen::VectorXd& x, const ConstraintSolverSettings& s,
                                    const SafeRange* safe) const {
    SolveResult result;
    const int n = rowCount();
    if (x.size() != n) x = Eigen::VectorXd::Zero(n);
    const double bNorm = b.norm();
    if (n == 0 || bNorm == 0.0) {
        x.setZero();
        result.converged = true;
        return result;
    }
    const double goal = s.tolerance * bNorm;
    Eigen::VectorXd r(n);
    // r = b − A x and ‖r‖ in one pass, from the kept product (no copy of it).
    auto measure = [&] { return residualAndNorm(b, productOf(x), r); };
    // A cold start is solved on every row: its error falls monotonically (Hestenes-Stiefel),
    // and there is no earlier solution whose residual would be local.
    const bool warm = !x.isZero(0.0);
    double residual = measure();
    // The scaled residual each region's CG may stop at, to check the proof (0: never).
    double safeGoal = 0.0;
    Decide decide; // while the region CGs may stop once the breaks are proven decided
    auto record = [&](Stop proof) {
        result.provenSafe = proof == Stop::Safe;
        result.breaksDecided = proof == Stop::BreaksDecided;
    };
    if (safe && safe->eigenvalueBound > 0.0) {
        record(proven(r, x, *safe, &safeGoal));
        if (!safe->breakLower.empty()) decide.safe = safe;
    }
    // Rows whose residual is below the floor are left out: all of them together hold at most
    // half the goal.
    const double floor = 0.5 * goal / std::sqrt(double(n));
    Taken& taken = taken_;
    if (warm) {
        taken.clear(particles_.size());
        marks_.fit(size_t(n), particles_.size());
    }
    size_t solved = 0;            // rows of the last region
    bool solvedEverything = false; // once a solve took every row, so do the rounds after it
    bool safeFloor = true;         // regions leave out what the safe stop allows (until it fails once)
    for (int hops = kFirstHops; !result.provenSafe && !result.breaksDecided && residual > goal &&
                                result.iterations < s.maxIterations;
         hops = std::min(2 * hops, kMostHops)) {
        Region region;
        // While the solve may stop when proven safe, the rows whose scaled residuals together
        // hold at most half the scaled residual that stop needs are left out too.
        if (warm && !solvedEverything)
            region = regionAround(r, floor, safeFloor ? 0.5 * safeGoal / std::sqrt(double(n)) : 0.0, hops, taken);
        // A region that stopped growing (CG met the null space inside it) gives way to all rows.
        const bool everything = solvedEverything || !warm || 2 * region.rows.size() >= size_t(n) ||
                                region.rows.size() == solved;
        solved = region.rows.size();
        if (everything) region = everyRow(), solvedEverything = true;
        const Stop stop = solveRegion(region, r, everything ? goal : 0.5 * goal, safeGoal, decide, bNorm, x,
                                      s, result);
        updateProduct(region, x);
        if (stop == Stop::BreaksDecided) { // proven on the whole residual
            record(stop);
            residual = decide.residual;
            break;
        }
        residual = measure();
        if (stop == Stop::Safe) {
            record(proven(r, x, *safe, nullptr));
            // Not proven where CG stopped for it: once more on a region that leaves out only
            // what the tolerance allows, then the safe rule is given up, on to the tolerance.
            if (safeFloor) safeFloor = false;
            else safeGoal = 0.0;
            continue;
        }
        if (everything) break;
    }
    result.residual = residual / bNorm;
    result.converged = residual <= goal || result.provenSafe || result.breaksDecided;
    return result;
}

Eigen::SparseMatrix<double> ConstraintSystem::assemble() const {
    // A_kl = n_k·n_l (±1/m of each shared particle): links meet only at their end particles.
    std::vector<std::vector<int>> rowsOf(particleCount());
    for (int k = 0; k < rowCount(); ++k) {
        rowsOf[rowA_[k]].push_back(k);
        rowsOf[rowB_[k]].push_back(k);
    }
    std::vector<Eigen::Triplet<double>> entries;
    for (int i = 0; i < particleCount(); ++i) {
        if (inverseMass_[i] == 0.0) continue;
        for (int k : rowsOf[i])
            for (int l : rowsOf[i]) {
                const double sk = rowA_[k] == i ? 1.0 : -1.0, sl = rowA_[l] == i ? 1.0 : -1.0;
                entries.emplace_back(k, l, sk * sl * inverseMass_[i] * normal_[k].dot(normal_[l]));
            }
    }
    Eigen::SparseMatrix<double> a(rowCount(), rowCount());
    a.setFromTriplets(entries.begin(), entries.end());
    return a;
}

} // namespace shatter::lattice
