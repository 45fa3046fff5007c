#include <shatter/plugin/lattice/Slivers.h>

#include <shatter/plugin/geometry/UnionFind.h>

#include <algorithm>
#include <cmath>

namespace shatter::lattice {

double tetQuality(const TetMesh& mesh, const Tet& t) {
    double longest = 0.0;
    for (int i = 0; i < 4; ++i)
        for (int j = i + 1; j < 4; ++j) longest = std::max(longest, (mesh.nodes[t[i]] - mesh.nodes[t[j]]).norm());
    return 6.0 * std::sqrt(2.0) * std::abs(signedVolume(mesh, t)) / (longest * longest * longest);
}

std::vector<int> sliverTets(const TetMesh& mesh, double threshold) {
    std::vector<int> out;
    for (int t = 0; t < int(mesh.tets.size()); ++t)
        if (tetQuality(mesh, mesh.tets[t]) < threshold) out.push_back(t);
    return out;
}

SliverBinding bindSlivers(Lattice& lattice, double threshold) {
    SliverBinding out;
    const int n = lattice.particleCount();
    std::vector<char> sliver(n, 0);
    for (int t : sliverTets(lattice.mesh(), threshold)) sliver[t] = 1, ++out.slivers;
    if (out.slivers == 0) return out;
    std::vector<char> bound(lattice.linkCount(), 0);
    geometry::UnionFind groups(n); // tets joined by bound links
    auto bind = [&](int link) {
        bound[link] = 1;
        groups.unite(lattice.links()[link].a, lattice.links()[link].b);
    };
    // The link across the largest face of `t` among those `allowed`, or -1.
    auto largest = [&](int t, auto allowed) {
        int best = -1;
        for (int k : lattice.linksOf(t))
            if (allowed(k) && (best < 0 || lattice.links()[k].area > lattice.links()[best].area)) best = k;
        return best;
    };
    for (int t = 0; t < n; ++t) {
        if (!sliver[t]) continue;
        int k = largest(t, [&](int link) { return !sliver[lattice.otherEnd(link, t)]; });
        if (k < 0) k = largest(t, [](int) { return true; });
        if (k >= 0) bind(k);
    }
    // Groups of slivers only join the neighbour across their largest outer face, until none is
    // left (each round joins every such group to another, so the rounds end).
    for (bool again = true; again;) {
        again = false;
        std::vector<char> solid(n, 0);
        for (int t = 0; t < n; ++t)
            if (!sliver[t]) solid[groups.find(t)] = 1;
        std::vector<int> best(n, -1); // per sliver-only group root: its largest link out
        for (int t = 0; t < n; ++t) {
            const int r = groups.find(t);
            if (solid[r]) continue;
            for (int k : lattice.linksOf(t)) {
                if (groups.find(lattice.otherEnd(k, t)) == r) continue;
                if (best[r] < 0 || lattice.links()[k].area > lattice.links()[best[r]].area) best[r] = k;
            }
        }
        for (int r = 0; r < n; ++r)
            if (best[r] >= 0 && !bound[best[r]]) bind(best[r]), again = true;
    }
    for (int k = 0; k < lattice.linkCount(); ++k)
        if (bound[k]) {
            lattice.scaleStrength(k, INFINITY);
            out.links.push_back(k);
        }
    return out;
}

} // namespace shatter::lattice
