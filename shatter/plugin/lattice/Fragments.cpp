#include <shatter/plugin/lattice/Fragments.h>

#include <shatter/plugin/geometry/UnionFind.h>

#include <algorithm>
#include <cmath>

namespace shatter::lattice {

std::vector<std::vector<int>> connectedComponents(const Lattice& lattice, const std::vector<int>& particles) {
    // Position in `sorted` of each lattice particle (-1: not in the piece): a dense table is
    // cheaper than a hash for the 50,000 particles of a statue's anchored rest.
    std::vector<int> local(lattice.particleCount(), -1);
    std::vector<int> sorted = particles;
    // (A piece's particles are sorted already: checked in one pass, where the sort took n log n.)
    if (!std::is_sorted(sorted.begin(), sorted.end())) std::sort(sorted.begin(), sorted.end());
    for (int i = 0; i < int(sorted.size()); ++i) local[sorted[i]] = i;
    geometry::UnionFind sets(int(sorted.size()));
    for (int i = 0; i < int(sorted.size()); ++i)
        for (int k : lattice.linksOf(sorted[i])) {
            const Link& l = lattice.links()[k];
            if (l.broken || l.a != sorted[i]) continue;
            if (local[l.b] >= 0) sets.unite(i, local[l.b]);
        }
    // Roots are the smallest member (UnionFind keeps the smaller index as root), so components
    // come out ordered by their smallest particle.
    std::vector<int> componentOfRoot(sorted.size(), -1);
    std::vector<std::vector<int>> out;
    for (int i = 0; i < int(sorted.size()); ++i) {
        const int root = sets.find(i);
        if (componentOfRoot[root] < 0) {
            componentOfRoot[root] = int(out.size());
            out.emplace_back();
        }
        out[componentOfRoot[root]].push_back(sorted[i]);
    }
    return out;
}

geometry::MassProperties tetMassProperties(const TetMesh& mesh, const Tet& tet, double density) {
    // Second moment about the first corner: V/20 (Σ vᵢvᵢᵀ + (Σvᵢ)(Σvᵢ)ᵀ) for corners v
    // relative to it (the tet's covariance), shifted to the centroid.
    const Eigen::Vector3d& o = mesh.nodes[tet[0]];
    const Eigen::Vector3d v1 = mesh.nodes[tet[1]] - o, v2 = mesh.nodes[tet[2]] - o, v3 = mesh.nodes[tet[3]] - o;
    const double volume = v1.dot(v2.cross(v3)) / 6.0;
    const Eigen::Vector3d sum = v1 + v2 + v3;
    Eigen::Matrix3d second = v1 * v1.transpose() + v2 * v2.transpose() + v3 * v3.transpose() + sum * sum.transpose();
    second *= volume / 20.0;
    const Eigen::Vector3d c = sum / 4.0; // centroid relative to o
    second -= volume * c * c.transpose();
    geometry::MassProperties m;
    m.volume = volume;
    m.mass = volume * density;
    m.centerOfMass = o + c;
    m.inertia = density * (second.trace() * Eigen::Matrix3d::Identity() - second);
    return m;
}

namespace {

// The tets' mass properties summed in the order of `particles` (massOf(p): tet p's).
template <class MassOf>
geometry::MassProperties sumOverTets(const std::vector<int>& particles, const MassOf& massOf) {
    geometry::MassProperties total;
    bool first = true;
    for (int p : particles) {
        if (first) {
            total = massOf(p);
            first = false;
        } else {
            total += massOf(p);
        }
    }
    return total;
}

} // namespace

geometry::MassProperties pieceMassProperties(const Lattice& lattice, const std::vector<int>& particles) {
    return sumOverTets(particles, [&](int p) {
        return tetMassProperties(lattice.mesh(), lattice.mesh().tets[p], lattice.material().density);
    });
}

geometry::MassProperties pieceMassProperties(const std::vector<geometry::MassProperties>& tetMass,
                                             const std::vector<int>& particles) {
    return sumOverTets(particles, [&](int p) -> const geometry::MassProperties& { return tetMass[size_t(p)]; });
}

std::vector<std::array<int, 3>> surfaceFaces(const Lattice& lattice, const std::vector<int>& particles) {
    // A flag per tet of the mesh, not a search per face: the anchored rest of a 55,000-tet body
    // is walked again each time a piece breaks off it.
    std::vector<int> copy; // only for an unsorted list (a piece's particles are sorted)
    if (!std::is_sorted(particles.begin(), particles.end())) {
        copy = particles;
        std::sort(copy.begin(), copy.end());
    }
    const std::vector<int>& sorted = copy.empty() ? particles : copy;
    std::vector<char> inPiece(lattice.mesh().tets.size(), 0);
    for (int t : sorted) inPiece[size_t(t)] = 1;
    std::vector<std::array<int, 3>> out;
    for (int t : sorted) {
        const auto faces = outwardFaces(lattice.mesh().tets[t]);
        for (int k = 0; k < 4; ++k) {
            const int n = lattice.faces().neighbour[t][k];
            if (n < 0 || !inPiece[size_t(n)]) out.push_back(faces[k]);
        }
    }
    return out;
}

double pieceSize(const Lattice& lattice, const std::vector<int>& particles, const Eigen::Vector3d& centre) {
    const auto& nodes = lattice.mesh().nodes;
    double farthest = 0.0;
    for (int t : particles)
        for (int n : lattice.mesh().tets[t]) farthest = std::max(farthest, (nodes[n] - centre).squaredNorm());
    return 2.0 * std::sqrt(farthest);
}

double convexityDefect(const Lattice& lattice, const std::vector<int>& particles) {
    const auto& nodes = lattice.mesh().nodes;
    std::vector<int> corners;
    corners.reserve(4 * particles.size());
    for (int t : particles)
        for (int n : lattice.mesh().tets[t]) corners.push_back(n);
    std::sort(corners.begin(), corners.end());
    corners.erase(std::unique(corners.begin(), corners.end()), corners.end());
    double defect = 0.0;
    for (const auto& f : surfaceFaces(lattice, particles)) {
        const Eigen::Vector3d& a = nodes[f[0]];
        const Eigen::Vector3d n = (nodes[f[1]] - a).cross(nodes[f[2]] - a).normalized(); // outward
        for (int c : corners) defect = std::max(defect, n.dot(nodes[c] - a));
    }
    return defect;
}

bool isConvexPiece(const Lattice& lattice, const std::vector<int>& particles, double tolerance, int maxTets) {
    if (particles.empty() || int(particles.size()) > maxTets) return false;
    if (particles.size() == 1) return true; // a tet
    double volume = 0.0;
    for (int p : particles) volume += lattice.particles()[p].volume;
    return convexityDefect(lattice, particles) <= tolerance * std::cbrt(volume);
}

int largestPart(const std::vector<std::vector<int>>& parts) {
    return int(std::max_element(parts.begin(), parts.end(), [](const auto& a, const auto& b) { return a.size() < b.size(); }) -
               parts.begin());
}

int partKeepingTheBody(const Lattice& lattice, const LatticePiece& piece, const std::vector<std::vector<int>>& parts,
                       double tolerance, int maxTets) {
    if (parts.empty()) return -1;
    const int index = largestPart(parts);
    const std::vector<int>& largest = parts[size_t(index)];
    // A static body stays static: an anchored piece keeps it only for an anchored part.
    const bool anchored = std::any_of(largest.begin(), largest.end(), [&](int p) { return lattice.particles()[p].fixed; });
    if (anchored != piece.anchored || 2 * largest.size() <= piece.particles.size()) return -1;
    if (isConvexPiece(lattice, largest, tolerance, maxTets)) return -1;
    return index;
}

} // namespace shatter::lattice
