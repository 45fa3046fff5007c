#include <shatter/plugin/lattice/TetFaces.h>

#include <shatter/plugin/geometry/UnionFind.h>

#include <algorithm>

namespace shatter::lattice {

namespace {

struct FaceKey {
    std::array<int, 3> sorted;
    int tet;
    int local;
    bool operator<(const FaceKey& o) const {
        if (sorted != o.sorted) return sorted < o.sorted;
        return tet != o.tet ? tet < o.tet : local < o.local;
    }
};

} // namespace

TetFaces buildTetFaces(const TetMesh& mesh) {
    TetFaces out;
    const int n = int(mesh.tets.size());
    out.neighbour.assign(n, {-1, -1, -1, -1});
    std::vector<FaceKey> keys;
    keys.reserve(size_t(n) * 4);
    for (int t = 0; t < n; ++t) {
        const auto faces = outwardFaces(mesh.tets[t]);
        for (int k = 0; k < 4; ++k) {
            std::array<int, 3> s = faces[k];
            std::sort(s.begin(), s.end());
            keys.push_back({s, t, k});
        }
    }
    std::sort(keys.begin(), keys.end());
    for (size_t i = 0; i < keys.size();) {
        size_t j = i + 1;
        while (j < keys.size() && keys[j].sorted == keys[i].sorted) ++j;
        if (j - i == 1) {
            ++out.boundaryCount;
        } else if (j - i == 2) {
            const FaceKey& a = keys[i];
            const FaceKey& b = keys[i + 1];
            out.neighbour[a.tet][a.local] = b.tet;
            out.neighbour[b.tet][b.local] = a.tet;
            out.shared.push_back({a.tet, b.tet, outwardFaces(mesh.tets[a.tet])[a.local]});
        } else if (out.overusedTet < 0) {
            out.overusedTet = keys[i + 2].tet;
            out.overusedFace = keys[i + 2].local;
        }
        i = j;
    }
    // Links in the order of their first tet, so that link numbering follows the mesh file.
    std::stable_sort(out.shared.begin(), out.shared.end(), [](const SharedFace& x, const SharedFace& y) {
        return x.tetA != y.tetA ? x.tetA < y.tetA : x.tetB < y.tetB;
    });
    return out;
}

int connectedPieces(const TetFaces& faces, std::vector<int>& pieceOfTet) {
    const int n = int(faces.neighbour.size());
    geometry::UnionFind sets(n);
    for (const SharedFace& f : faces.shared) sets.unite(f.tetA, f.tetB);
    pieceOfTet.assign(n, -1);
    std::vector<int> pieceOfRoot(n, -1);
    int pieces = 0;
    for (int t = 0; t < n; ++t) {
        const int root = sets.find(t);
        if (pieceOfRoot[root] < 0) pieceOfRoot[root] = pieces++;
        pieceOfTet[t] = pieceOfRoot[root];
    }
    return pieces;
}

} // namespace shatter::lattice
