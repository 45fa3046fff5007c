#include <shatter/plugin/lattice/LatticePiece.h>

#include <shatter/plugin/lattice/EigenvalueBound.h>

#include <algorithm>

namespace shatter::lattice {

namespace {

std::vector<int> candidateLinks(const Lattice& lattice, const std::vector<int>& particles) {
    // Each link once, from its lower end; the system drops those leaving the piece.
    std::vector<int> links;
    for (int p : particles)
        for (int k : lattice.linksOf(p))
            if (lattice.links()[k].a == p && !lattice.links()[k].broken) links.push_back(k);
    std::sort(links.begin(), links.end());
    return links;
}

} // namespace

ConstraintSystem& LatticePiece::constraintSystem(const Lattice& lattice) {
    if (!system) {
        system = std::make_unique<ConstraintSystem>(lattice, particles, candidateLinks(lattice, particles));
        if (lambda.size() != system->rowCount()) lambda = Eigen::VectorXd::Zero(system->rowCount());
    }
    return *system;
}

void LatticePiece::rebuild(const Lattice& lattice) {
    if (system && lambda.size() == system->rowCount() && system->canRestrictTo(lattice, particles)) {
        system->restrictTo(lattice, particles, lambda); // the same piece after breaks, or a part of it
        return;
    }
    std::unique_ptr<ConstraintSystem> old = std::move(system);
    system = std::make_unique<ConstraintSystem>(lattice, particles, candidateLinks(lattice, particles));
    Eigen::VectorXd carried = Eigen::VectorXd::Zero(system->rowCount());
    // Both systems list their links ascending: carry λ over by a merge walk.
    if (old && lambda.size() == old->rowCount()) {
        const std::vector<int>& from = old->links();
        const std::vector<int>& to = system->links();
        for (size_t i = 0, j = 0; i < from.size() && j < to.size();) {
            if (from[i] < to[j]) ++i;
            else if (to[j] < from[i]) ++j;
            else carried[Eigen::Index(j++)] = lambda[Eigen::Index(i++)];
        }
    }
    lambda = std::move(carried);
}

void LatticePiece::inheritSolver(LatticePiece& parent, const Lattice& lattice) {
    system = std::move(parent.system);
    lambda = std::move(parent.lambda);
    eigenvalueBound = parent.eigenvalueBound; // a principal submatrix's eigenvalues are no smaller
    rebuild(lattice);
}

const NearestParticles& LatticePiece::nearestGrid(const Lattice& lattice) {
    if (!grid_) {
        std::vector<Eigen::Vector3d> points;
        points.reserve(particles.size());
        for (int p : particles) points.push_back(lattice.particles()[p].position);
        grid_ = std::make_unique<NearestParticles>(std::move(points));
    }
    return *grid_;
}

bool LatticePiece::contains(int particle) const { return std::binary_search(particles.begin(), particles.end(), particle); }

LatticePiece makePiece(const Lattice& lattice, std::vector<int> particles) {
    LatticePiece piece;
    // (The parts fragmentParts makes are sorted already.)
    if (!std::is_sorted(particles.begin(), particles.end())) std::sort(particles.begin(), particles.end());
    piece.particles = std::move(particles);
    piece.anchored = std::any_of(piece.particles.begin(), piece.particles.end(),
                                 [&](int p) { return lattice.particles()[p].fixed; });
    // The whole body before anything broke: every later piece's system keeps part of its rows,
    // links joined again included (EigenvalueBound.h).
    if (int(piece.particles.size()) == lattice.particleCount() && lattice.brokenCount() == 0)
        piece.eigenvalueBound = scaledEigenvalueLowerBound(piece.constraintSystem(lattice));
    return piece;
}

} // namespace shatter::lattice
