#include <shatter/plugin/lattice/PieceLoads.h>

#include <algorithm>
#include <cmath>
#include <cstring>

namespace shatter::lattice {

const Eigen::VectorXd& pieceLoads(const Lattice& lattice, LatticePiece& piece, const Eigen::Vector3d& gravity,
                                  std::span<const Impact> impacts, int impactParticles) {
    const int n = int(piece.particles.size());
    LatticePiece::KeptLoads& kept = piece.loads;
    // Compared bit for bit: an anchored piece's g in mesh axes is the same every step.
    if (kept.gravity.size() != 3 * n || std::memcmp(kept.gravityOf.data(), gravity.data(), sizeof(double) * 3) != 0) {
        kept.gravity = Eigen::VectorXd::Zero(3 * n);
        // Fixed particles take any load; they carry none of their own.
        for (int i = 0; i < n; ++i) {
            const Particle& p = lattice.particles()[piece.particles[i]];
            if (!p.fixed) kept.gravity.segment<3>(3 * i) = p.mass * gravity;
        }
        kept.gravityOf = gravity;
        kept.loads = kept.gravity;
        kept.touched.clear();
    }
    // The last step's impacts taken off: their particles' loads set back to gravity alone, so
    // every load is its gravity plus this step's impacts added in order, as if formed afresh.
    for (int i : kept.touched) kept.loads.segment<3>(3 * i) = kept.gravity.segment<3>(3 * i);
    kept.touched.clear();
    for (const Impact& impact : impacts) {
        const auto nearest = nearestParticles(lattice, piece, impact.point, impact.particle, impactParticles);
        addPointForce(nearest, impact.force, kept.loads);
        for (const auto& [distance, i] : nearest) kept.touched.push_back(i);
    }
    return kept.loads;
}

std::vector<std::pair<double, int>> nearestParticles(const Lattice& lattice, LatticePiece& piece,
                                                     const Eigen::Vector3d& point, int particle, int k) {
    const auto& particles = piece.particles;
    if (particle < 0 || particle >= int(particles.size()) || k > 5) return piece.nearestGrid(lattice).nearest(point, k);
    std::vector<std::pair<double, int>> near;
    near.reserve(5); // the tet and its 4 face neighbours: one allocation
    const int tet = particles[particle];
    near.emplace_back((lattice.particles()[tet].position - point).squaredNorm(), particle);
    const int size = int(particles.size()), missing = lattice.particleCount() - size;
    for (int n : lattice.faces().neighbour[tet]) {
        if (n < 0) continue;
        // Where n can be in the piece's list (ascending, distinct): within |n − tet| places of
        // the tet, and fewer than that by at most the lattice's particles the piece lacks. The
        // same search as over the whole list, over at most `missing` + 1 places (one, in a
        // whole body).
        const int gap = std::abs(n - tet), nearest = std::max(1, gap - missing);
        const int from = n > tet ? particle + nearest : std::max(0, particle - gap);
        const int to = n > tet ? std::min(size, particle + gap + 1) : particle - nearest + 1;
        if (from >= to) continue;
        const auto it = std::lower_bound(particles.begin() + from, particles.begin() + to, n);
        if (it == particles.begin() + to || *it != n) continue;
        near.emplace_back((lattice.particles()[n].position - point).squaredNorm(), int(it - particles.begin()));
    }
    std::sort(near.begin(), near.end());
    near.resize(std::min<size_t>(near.size(), size_t(k)));
    return near;
}

void addPointForce(const std::vector<std::pair<double, int>>& nearest, const Eigen::Vector3d& force,
                   Eigen::VectorXd& loads) {
    const int k = int(nearest.size());
    if (k <= 0) return;
    // Inverse distance, softened by a thousandth of the farthest of the k so a contact right
    // on a centroid does not divide by zero.
    const double soft = 1e-3 * std::sqrt(nearest[k - 1].first) + 1e-12;
    double total = 0.0;
    for (int j = 0; j < k; ++j) total += 1.0 / (std::sqrt(nearest[j].first) + soft);
    for (int j = 0; j < k; ++j) {
        const double w = 1.0 / (std::sqrt(nearest[j].first) + soft) / total;
        loads.segment<3>(3 * nearest[j].second) += w * force;
    }
}

bool loadsChanged(const Lattice& lattice, const LatticePiece& piece, const Eigen::VectorXd& loads, double fraction) {
    if (piece.analysedLoads.size() != loads.size()) return true;
    // A run of particles at a time first: loads with the same bits give a change of 0 (or NaN,
    // which is no change above the fraction either), and most runs of a resting piece are so.
    constexpr int kRun = 64;
    for (int first = 0, count = int(piece.particles.size()); first < count; first += kRun) {
        const int end = std::min(count, first + kRun);
        if (std::memcmp(loads.data() + 3 * first, piece.analysedLoads.data() + 3 * first,
                        sizeof(double) * size_t(3 * (end - first))) == 0)
            continue;
        for (int i = first; i < end; ++i) {
            // Equal loads (a resting piece's most) give a change of 0 without the square root.
            if (loads.segment<3>(3 * i) == piece.analysedLoads.segment<3>(3 * i)) continue;
            const double change = (loads.segment<3>(3 * i) - piece.analysedLoads.segment<3>(3 * i)).norm();
            if (change == 0.0) continue;
            double weakest = INFINITY;
            for (int k : lattice.linksOf(piece.particles[i]))
                if (!lattice.links()[k].broken) weakest = std::min(weakest, lattice.links()[k].strength);
            if (change > fraction * weakest) return true;
        }
    }
    return false;
}

} // namespace shatter::lattice
