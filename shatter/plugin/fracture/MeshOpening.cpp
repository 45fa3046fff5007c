#include <shatter/plugin/fracture/MeshOpening.h>

#include <shatter/plugin/common/InputError.h>
#include <shatter/plugin/fracture/Tearing.h>
#include <shatter/plugin/geometry/UnionFind.h>

#include <algorithm>

namespace shatter::fracture {

namespace {

// Each primitive's neighbours over the unbroken connections, in the order of the connections
// (the order tearMesh looks at them for a face's T-junction corners).
struct Neighbours {
    std::vector<int> offset, list;
    Neighbours(const geometry::PhysicalMesh& body, const std::vector<bool>& broken) {
        const size_t n = body.primitives.size();
        offset.assign(n + 1, 0);
        for (size_t c = 0; c < body.connections.size(); ++c)
            if (!broken[c]) ++offset[size_t(body.connections[c].first) + 1], ++offset[size_t(body.connections[c].second) + 1];
        for (size_t p = 0; p < n; ++p) offset[p + 1] += offset[p];
        list.resize(size_t(offset[n]));
        std::vector<int> next(offset.begin(), offset.end() - 1);
        for (size_t c = 0; c < body.connections.size(); ++c) {
            if (broken[c]) continue;
            const auto [a, b] = body.connections[c];
            list[size_t(next[size_t(a)]++)] = b;
            list[size_t(next[size_t(b)]++)] = a;
        }
    }
    const int* begin(int p) const { return list.data() + offset[size_t(p)]; }
    const int* end(int p) const { return list.data() + offset[size_t(p) + 1]; }
};

// An id split off: the carriers (ascending) that take the new id.
struct Split {
    int id = -1;
    std::vector<int> carriers;
    int newId = -1;
};

} // namespace

std::optional<MeshOpening> openMesh(geometry::PhysicalMesh& body, const std::vector<bool>& broken) {
    if (broken.size() != body.connections.size())
        throw InputError("body '" + body.name + "': " + std::to_string(broken.size()) + " broken flags for " +
                         std::to_string(body.connections.size()) + " connections");
    const int n = int(body.primitives.size());
    const int visualCount = int(body.visual.positions.size());
    {
        geometry::UnionFind parts(n);
        int count = n;
        for (size_t c = 0; c < body.connections.size(); ++c)
            if (!broken[c] && parts.unite(body.connections[c].first, body.connections[c].second)) --count;
        if (count > 1) return std::nullopt;
    }
    const Neighbours neighbours(body, broken);
    MeshOpening opening;

    // The ids shared across a broken connection, each with the two primitives (the seeds of
    // its floods).
    std::vector<std::pair<int, int>> seeds; // (id, primitive)
    opening.connectionIndex.resize(body.connections.size());
    int kept = 0;
    for (size_t c = 0; c < body.connections.size(); ++c) {
        if (!broken[c]) {
            opening.connectionIndex[c] = kept++;
            continue;
        }
        opening.connectionIndex[c] = -1;
        const auto [a, b] = body.connections[c];
        opening.broken.emplace_back(a, b);
        for (int id : body.primitives[size_t(a)].globalIds())
            if (vertexWithId(body.primitives[size_t(b)], id) >= 0) seeds.emplace_back(id, a), seeds.emplace_back(id, b);
    }
    std::sort(seeds.begin(), seeds.end());
    seeds.erase(std::unique(seeds.begin(), seeds.end()), seeds.end());

    // The floods: per id, the groups of its carriers that hang together. Before the tear they
    // all did, so every group holds a seed.
    std::vector<int> floodedFor(size_t(n), -1); // the id whose flood reached the primitive last
    std::vector<Split> splits;
    std::vector<int> queue;
    for (size_t s = 0; s < seeds.size();) {
        const int id = seeds[s].first;
        std::vector<std::vector<int>> groups;
        for (; s < seeds.size() && seeds[s].first == id; ++s) {
            const int seed = seeds[s].second;
            if (floodedFor[size_t(seed)] == id) continue;
            floodedFor[size_t(seed)] = id;
            queue.assign(1, seed);
            for (size_t head = 0; head < queue.size(); ++head)
                for (const int* q = neighbours.begin(queue[head]); q != neighbours.end(queue[head]); ++q)
                    if (floodedFor[size_t(*q)] != id && vertexWithId(body.primitives[size_t(*q)], id) >= 0) {
                        floodedFor[size_t(*q)] = id;
                        queue.push_back(*q);
                    }
            std::sort(queue.begin(), queue.end());
            groups.push_back(queue);
        }
        if (groups.size() < 2) continue; // still welded: the tear has not reached this vertex
        std::sort(groups.begin(), groups.end(), [](const auto& x, const auto& y) { return x.front() < y.front(); });
        for (size_t g = 0; g < groups.size(); ++g) {
            opening.touched.insert(opening.touched.end(), groups[g].begin(), groups[g].end());
            if (g > 0) splits.push_back({id, std::move(groups[g]), -1});
        }
    }
    std::sort(opening.touched.begin(), opening.touched.end());
    opening.touched.erase(std::unique(opening.touched.begin(), opening.touched.end()), opening.touched.end());

    // New ids: visual ones after the old visual ids, inner ones at the end.
    for (const Split& split : splits) opening.visualIdsAdded += split.id < visualCount ? 1 : 0;
    int nextVisual = visualCount, nextInner = body.globalIdCount + opening.visualIdsAdded;
    std::vector<char> splitVisual(size_t(visualCount), 0);
    for (Split& split : splits) {
        if (split.id < visualCount) {
            split.newId = nextVisual++;
            splitVisual[size_t(split.id)] = 1;
        } else {
            split.newId = nextInner++;
        }
    }
    opening.idsSplit = int(splits.size());
    // Per slot (primitive, vertex) given a new id, sorted.
    std::vector<std::pair<std::pair<int, int>, int>> renamed;
    for (const Split& split : splits)
        for (int p : split.carriers) renamed.push_back({{p, vertexWithId(body.primitives[size_t(p)], split.id)}, split.newId});
    std::sort(renamed.begin(), renamed.end());
    auto newIdOf = [&](int p, int vertex) {
        const auto it = std::lower_bound(renamed.begin(), renamed.end(), std::pair<std::pair<int, int>, int>({p, vertex}, -1));
        if (it != renamed.end() && it->first == std::pair<int, int>(p, vertex)) return it->second;
        const int id = body.primitives[size_t(p)].globalIds()[size_t(vertex)];
        return id < visualCount ? id : id + opening.visualIdsAdded;
    };

    // Faces with a corner that split, or whose primitives lost a connection (a T-junction
    // corner, carried by a neighbour piece, may have lost its piece): their corners as tearMesh
    // finds them, from the face's primitives or, for a T-junction corner, their neighbours.
    auto& faces = body.visual.faces;
    std::vector<char> affected(faces.size(), 0);
    for (const auto& [a, b] : opening.broken)
        for (int p : {a, b})
            if (const int f = body.sourceFace[size_t(p)]; f >= 0) affected[size_t(f)] = 1;
    bool any = std::find(affected.begin(), affected.end(), 1) != affected.end();
    for (size_t f = 0; f < faces.size() && !splits.empty(); ++f)
        for (int v : faces[f])
            if (v < visualCount && splitVisual[size_t(v)]) affected[f] = any = 1;
    if (any) {
        std::vector<std::vector<int>> owners(faces.size());
        for (int p = 0; p < n; ++p)
            if (const int f = body.sourceFace[size_t(p)]; f >= 0 && affected[size_t(f)]) owners[size_t(f)].push_back(p);
        for (size_t f = 0; f < faces.size(); ++f) {
            if (!affected[f]) continue;
            auto& own = owners[f];
            if (own.empty()) // a face of a closed convex part: the primitive that carries all its corners
                for (int p = 0; p < n && own.empty(); ++p)
                    if (std::all_of(faces[f].begin(), faces[f].end(),
                                    [&](int v) { return vertexWithId(body.primitives[size_t(p)], v) >= 0; }))
                        own.push_back(p);
            if (own.empty())
                throw InputError("body '" + body.name + "': visual face " + std::to_string(f) + " belongs to no primitive");
            std::vector<int> face;
            for (int v : faces[f]) {
                int id = -1;
                for (size_t o = 0; o < own.size() && id < 0; ++o)
                    if (const int k = vertexWithId(body.primitives[size_t(own[o])], v); k >= 0) id = newIdOf(own[o], k);
                for (size_t o = 0; o < own.size() && id < 0; ++o)
                    for (const int* q = neighbours.begin(own[o]); q != neighbours.end(own[o]) && id < 0; ++q)
                        if (const int k = vertexWithId(body.primitives[size_t(*q)], v); k >= 0) id = newIdOf(*q, k);
                if (id >= 0) face.push_back(id); // a T-junction corner torn from every piece goes (Tearing.cpp)
            }
            if (face.size() < 3)
                throw InputError("body '" + body.name + "': visual face " + std::to_string(f) + " has " +
                                 std::to_string(face.size()) + " corners on its primitives and their neighbours, not 3");
            if (face != faces[f]) {
                faces[f] = std::move(face);
                opening.faces.push_back(int(f));
            }
        }
    }

    // Tear edges: those at a split id are found again from its carriers (each edge a carrier
    // holds, in its ids now); the others stay.
    if (!splits.empty() && !body.tearEdges.empty()) {
        auto& edges = body.tearEdges;
        std::vector<std::pair<int, int>> found;
        for (int p : opening.touched) {
            const auto& g = body.primitives[size_t(p)].globalIds();
            for (int i = 0; i < int(g.size()); ++i)
                for (int j = i + 1; j < int(g.size()); ++j) {
                    const std::pair<int, int> e(std::min(g[size_t(i)], g[size_t(j)]), std::max(g[size_t(i)], g[size_t(j)]));
                    if (e.second >= visualCount || !std::binary_search(edges.begin(), edges.end(), e)) continue;
                    const int a = newIdOf(p, i), b = newIdOf(p, j);
                    found.emplace_back(std::min(a, b), std::max(a, b));
                }
        }
        std::erase_if(edges, [&](const auto& e) { return splitVisual[size_t(e.first)] || splitVisual[size_t(e.second)]; });
        edges.insert(edges.end(), found.begin(), found.end());
        std::sort(edges.begin(), edges.end());
        edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
    }

    // The ids themselves, the new visual vertices (where the ids they split from are), and the
    // connections left.
    auto next = renamed.begin();
    for (int p = 0; p < n; ++p) {
        const auto& g = body.primitives[size_t(p)].globalIds();
        const bool renamedHere = next != renamed.end() && next->first.first == p;
        const bool moved = opening.visualIdsAdded > 0 &&
                           std::any_of(g.begin(), g.end(), [&](int id) { return id >= visualCount; });
        if (!renamedHere && !moved) continue;
        std::vector<int> ids = g;
        for (int& id : ids) id = id < visualCount ? id : id + opening.visualIdsAdded;
        for (; next != renamed.end() && next->first.first == p; ++next) ids[size_t(next->first.second)] = next->second;
        body.primitives[size_t(p)].setGlobalIds(std::move(ids));
    }
    for (const Split& split : splits)
        if (split.id < visualCount) body.visual.positions.push_back(body.visual.positions[size_t(split.id)]);
    body.globalIdCount += opening.idsSplit;
    size_t write = 0;
    for (size_t c = 0; c < broken.size(); ++c)
        if (!broken[c]) body.connections[write++] = body.connections[c];
    body.connections.resize(write);
    return opening;
}

} // namespace shatter::fracture
