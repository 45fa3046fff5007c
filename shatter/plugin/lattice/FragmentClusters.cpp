#include <shatter/plugin/lattice/FragmentClusters.h>

#include <shatter/plugin/geometry/UnionFind.h>
#include <shatter/plugin/lattice/Fragments.h>

#include <algorithm>
#include <limits>
#include <utility>

namespace shatter::lattice {

namespace {

// The part of every particle of the lattice, -1 for those in none: a dense table, cheaper than
// a search or a hash for the 50,000 tets of a statue's anchored rest.
std::vector<int> partOfParticle(const Lattice& lattice, const std::vector<std::vector<int>>& parts) {
    std::vector<int> partOf(lattice.particleCount(), -1);
    for (int i = 0; i < int(parts.size()); ++i)
        for (int p : parts[i]) partOf[p] = i;
    return partOf;
}

// Mass and mass-weighted position sum of a set of parts: its centre of mass is moment / mass.
struct Centre {
    double mass = 0.0;
    Eigen::Vector3d moment = Eigen::Vector3d::Zero();
    Eigen::Vector3d at() const { return moment / mass; }
    void add(const Centre& other) {
        mass += other.mass;
        moment += other.moment;
    }
};

// Which parts go together (the rules are fragmentParts', FragmentClusters.h): groups() lists
// indices into `parts`, each group ascending, ordered by their first part. Deterministic: it
// depends only on the parts and the lattice, never on addresses or hash order.
class Clustering {
public:
    // `partOf`: partOfParticle of `parts` (fragmentParts uses it again to join the links).
    Clustering(const Lattice& lattice, const std::vector<std::vector<int>>& parts, const std::vector<int>& partOf,
               double minSize)
        : lattice_(lattice), parts_(parts), minSize_(minSize), n_(int(parts.size())), centre_(n_), fixed_(n_, 0),
          small_(n_, 0), neighbours_(n_) {
        for (int i = 0; i < n_; ++i) {
            for (int p : parts_[i]) {
                const Particle& particle = lattice_.particles()[p];
                fixed_[i] = fixed_[i] || particle.fixed;
                centre_[i].mass += particle.mass;
                centre_[i].moment += particle.mass * particle.position;
            }
            small_[i] = !fixed_[i] && pieceSize(lattice_, parts_[i], centre_[i].at()) < minSize_;
        }
        // The broken faces between a small part and each of its neighbours (area summed).
        for (int i = 0; i < n_; ++i) {
            if (!small_[i]) continue;
            for (int p : parts_[i])
                for (int k : lattice_.linksOf(p)) {
                    const int j = partOf[lattice_.otherEnd(k, p)];
                    if (j >= 0 && j != i) addArea(neighbours_[i], j, lattice_.links()[k].area);
                }
        }
    }

    std::vector<std::vector<int>> groups() {
        geometry::UnionFind sets(n_);
        growClusters(sets);
        joinDeficientGroups(sets);
        std::vector<int> groupOfRoot(n_, -1);
        std::vector<std::vector<int>> out;
        for (int i = 0; i < n_; ++i) {
            const int root = sets.find(i);
            if (groupOfRoot[root] < 0) {
                groupOfRoot[root] = int(out.size());
                out.emplace_back();
            }
            out[groupOfRoot[root]].push_back(i);
        }
        return out;
    }

private:
    static void addArea(std::vector<std::pair<int, double>>& areas, int neighbour, double area) {
        const auto it = std::find_if(areas.begin(), areas.end(), [&](const auto& a) { return a.first == neighbour; });
        if (it == areas.end()) areas.emplace_back(neighbour, area);
        else it->second += area;
    }

    // lattice::pieceSize of the union of `members` (part indices) about its centre of mass: the
    // largest of the members' sizes about that centre (the same bits: 2·sqrt is monotone).
    double size(const std::vector<int>& members, const Centre& centre) const {
        const Eigen::Vector3d c = centre.at();
        double largest = 0.0;
        for (int i : members) largest = std::max(largest, pieceSize(lattice_, parts_[i], c));
        return largest;
    }

    // Each untaken small part seeds a cluster grown by the nearest untaken small neighbour.
    void growClusters(geometry::UnionFind& sets) {
        std::vector<char> taken(n_, 0);
        for (int seed = 0; seed < n_; ++seed) {
            if (!small_[seed] || taken[seed]) continue;
            taken[seed] = 1;
            std::vector<int> members{seed};
            Centre centre = centre_[seed];
            while (size(members, centre) < minSize_) {
                const Eigen::Vector3d c = centre.at();
                int best = -1;
                double bestDistance = std::numeric_limits<double>::infinity();
                for (int m : members)
                    for (const auto& [j, area] : neighbours_[m]) {
                        if (!small_[j] || taken[j]) continue;
                        const double d = (centre_[j].at() - c).squaredNorm();
                        if (d < bestDistance || (d == bestDistance && j < best)) best = j, bestDistance = d;
                    }
                if (best < 0) break;
                taken[best] = 1;
                members.push_back(best);
                centre.add(centre_[best]);
                sets.unite(seed, best);
            }
        }
    }

    // Groups below the size with no large part join the neighbouring group they share the
    // largest broken area with, a loose one if they touch any (the tets that came loose leave,
    // in larger pieces), else an anchored one (they stay attached); in rounds decided on the
    // groups as they were at the start of the round.
    void joinDeficientGroups(geometry::UnionFind& sets) {
        for (bool again = true; again;) {
            again = false;
            std::vector<std::vector<int>> members(n_);
            std::vector<char> anchored(n_, 0); // by root
            for (int i = 0; i < n_; ++i) {
                members[sets.find(i)].push_back(i);
                anchored[sets.find(i)] = anchored[sets.find(i)] || fixed_[i];
            }
            std::vector<std::pair<int, int>> joins;
            for (int r = 0; r < n_; ++r) {
                if (members[r].empty()) continue;
                Centre centre;
                bool large = false;
                for (int i : members[r]) {
                    large = large || !small_[i];
                    centre.add(centre_[i]);
                }
                if (large || size(members[r], centre) >= minSize_) continue;
                std::vector<std::pair<int, double>> areas; // by neighbouring group root
                for (int i : members[r])
                    for (const auto& [j, area] : neighbours_[i])
                        if (sets.find(j) != r) addArea(areas, sets.find(j), area);
                int best = -1;
                double bestArea = -1.0;
                for (bool anchoredToo : {false, true}) {
                    for (const auto& [root, area] : areas)
                        if ((anchoredToo || !anchored[root]) && (area > bestArea || (area == bestArea && root < best)))
                            best = root, bestArea = area;
                    if (best >= 0) break;
                }
                if (best >= 0) joins.emplace_back(r, best);
            }
            for (const auto& [a, b] : joins) again = sets.unite(a, b) || again;
        }
    }

    const Lattice& lattice_;
    const std::vector<std::vector<int>>& parts_;
    const double minSize_;
    const int n_;
    std::vector<Centre> centre_;
    std::vector<char> fixed_; // holds a fixed particle
    std::vector<char> small_;
    std::vector<std::vector<std::pair<int, double>>> neighbours_; // small parts only
};

} // namespace

std::vector<std::vector<int>> fragmentParts(Lattice& lattice, LatticePiece& piece, double minSize) {
    std::vector<std::vector<int>> parts = connectedComponents(lattice, piece.particles);
    if (minSize <= 0.0 || parts.size() < 2) return parts; // nothing to merge
    // One table for the clustering and for the joining below: it is a pass over every particle
    // of the lattice.
    const std::vector<int> partOf = partOfParticle(lattice, parts);
    const std::vector<std::vector<int>> groups = Clustering(lattice, parts, partOf, minSize).groups();
    if (groups.size() == parts.size()) return parts;
    std::vector<int> groupOf(parts.size());
    for (int g = 0; g < int(groups.size()); ++g)
        for (int i : groups[g]) groupOf[i] = g;
    // Join the links between different parts of one group (a crack inside a part stays). Each
    // joins two parts, so it is found from one that is not the group's largest, which is skipped:
    // it may be the 50,000-tet anchored rest.
    for (const auto& group : groups) {
        if (group.size() < 2) continue;
        const int largest = *std::max_element(group.begin(), group.end(),
                                              [&](int a, int b) { return parts[a].size() < parts[b].size(); });
        for (int i : group) {
            if (i == largest) continue;
            for (int p : parts[i])
                for (int k : lattice.linksOf(p)) {
                    const int j = partOf[lattice.otherEnd(k, p)];
                    if (j >= 0 && j != i && groupOf[j] == groupOf[i]) lattice.joinLink(k);
                }
        }
    }
    std::vector<std::vector<int>> out;
    out.reserve(groups.size());
    for (const auto& group : groups) {
        std::vector<int> merged;
        for (int i : group) merged.insert(merged.end(), parts[i].begin(), parts[i].end());
        // (A group of one part, such as the 50,000-tet rest, is sorted already.)
        if (!std::is_sorted(merged.begin(), merged.end())) std::sort(merged.begin(), merged.end());
        out.push_back(std::move(merged));
    }
    if (out.size() == 1) piece.rebuild(lattice);
    return out;
}

} // namespace shatter::lattice
