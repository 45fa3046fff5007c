#include <shatter/plugin/fracture/Tearing.h>

#include <shatter/plugin/common/InputError.h>
#include <shatter/plugin/geometry/UnionFind.h>

#include <algorithm>

namespace shatter::fracture {

namespace {

// The primitives each visual face belongs to: those made from it (sourceFace), or for a face
// of a closed convex part (sourceFace −1) the primitive that carries all its ids.
std::vector<std::vector<int>> faceOwners(const geometry::PhysicalMesh& body) {
    const auto& faces = body.visual.faces;
    std::vector<std::vector<int>> owners(faces.size());
    for (int p = 0; p < int(body.primitives.size()); ++p)
        if (const int f = body.sourceFace[size_t(p)]; f >= 0) owners[size_t(f)].push_back(p);
    std::vector<std::vector<int>> carriers;
    for (int f = 0; f < int(faces.size()); ++f) {
        if (!owners[size_t(f)].empty()) continue;
        if (carriers.empty()) {
            carriers.resize(size_t(body.globalIdCount));
            for (int p = 0; p < int(body.primitives.size()); ++p)
                for (int id : body.primitives[size_t(p)].globalIds()) carriers[size_t(id)].push_back(p);
        }
        for (int p : carriers[size_t(faces[size_t(f)].front())]) {
            const bool all = std::all_of(faces[size_t(f)].begin(), faces[size_t(f)].end(),
                                         [&](int v) { return vertexWithId(body.primitives[size_t(p)], v) >= 0; });
            if (all) {
                owners[size_t(f)].push_back(p);
                break;
            }
        }
        if (owners[size_t(f)].empty())
            throw InputError("body '" + body.name + "': visual face " + std::to_string(f) + " belongs to no primitive");
    }
    return owners;
}

// The parts of tearMesh; their primitives are moved from `take` (body's own) when given,
// else copied.
TearResult tear(const geometry::PhysicalMesh& body, const std::vector<bool>& broken,
                std::vector<geometry::ConvexPolyhedron>* take);

} // namespace

int vertexWithId(const geometry::ConvexPolyhedron& p, int id) {
    const auto& ids = p.globalIds();
    const auto it = std::find(ids.begin(), ids.end(), id);
    return it == ids.end() ? -1 : int(it - ids.begin());
}

int largestPart(const TearResult& torn) {
    int largest = 0;
    for (int k = 1; k < int(torn.parents.size()); ++k)
        if (torn.parents[size_t(k)].size() > torn.parents[size_t(largest)].size()) largest = k;
    return largest;
}

TearResult tearMesh(const geometry::PhysicalMesh& body, const std::vector<bool>& broken) {
    return tear(body, broken, nullptr);
}

TearResult tearMesh(geometry::PhysicalMesh&& body, const std::vector<bool>& broken) {
    return tear(body, broken, &body.primitives);
}

namespace {

TearResult tear(const geometry::PhysicalMesh& body, const std::vector<bool>& broken,
                std::vector<geometry::ConvexPolyhedron>* take) {
    if (broken.size() != body.connections.size())
        throw InputError("body '" + body.name + "': " + std::to_string(broken.size()) + " broken flags for " +
                         std::to_string(body.connections.size()) + " connections");
    const int n = int(body.primitives.size());
    const int visualCount = int(body.visual.positions.size());
    // One slot per primitive vertex. The flood fill of the source, as unions: two vertices
    // with the same id stay one vertex when their primitives are still connected.
    std::vector<int> offset(size_t(n) + 1, 0);
    for (int p = 0; p < n; ++p) offset[size_t(p) + 1] = offset[size_t(p)] + int(body.primitives[size_t(p)].vertices().size());
    geometry::UnionFind slots(offset.back());
    geometry::UnionFind components(n);
    for (size_t c = 0; c < body.connections.size(); ++c) {
        if (broken[c]) continue;
        const auto [a, b] = body.connections[c];
        components.unite(a, b);
        const auto& ga = body.primitives[size_t(a)].globalIds();
        const auto& gb = body.primitives[size_t(b)].globalIds();
        for (size_t k = 0; k < ga.size(); ++k)
            for (size_t l = 0; l < gb.size(); ++l)
                if (ga[k] == gb[l]) slots.unite(offset[size_t(a)] + int(k), offset[size_t(b)] + int(l));
    }

    TearResult result;
    // Parts in the order of their first primitive; primitives ascending within a part.
    const size_t count = size_t(n);
    std::vector<int> partOf(count), indexInPart(count);
    std::vector<int> partOfRoot(count, -1);
    for (int p = 0; p < n; ++p) {
        int& part = partOfRoot[size_t(components.find(p))];
        if (part < 0) {
            part = int(result.parents.size());
            result.parents.emplace_back();
        }
        partOf[size_t(p)] = part;
        indexInPart[size_t(p)] = int(result.parents[size_t(part)].size());
        result.parents[size_t(part)].push_back(p);
    }
    const int partCount = int(result.parents.size());

    // New ids per part: visual classes first (in the order met), then the inner ones.
    std::vector<int> localId(size_t(offset.back()), -1); // per slot root
    result.originalIds.resize(size_t(partCount));
    std::vector<int> visualIds(size_t(partCount), 0);
    for (int part = 0; part < partCount; ++part)
        for (const bool visual : {true, false})
            for (int p : result.parents[size_t(part)]) {
                const auto& g = body.primitives[size_t(p)].globalIds();
                for (int k = 0; k < int(g.size()); ++k) {
                    if ((g[size_t(k)] < visualCount) != visual) continue;
                    int& id = localId[size_t(slots.find(offset[size_t(p)] + k))];
                    if (id >= 0) continue;
                    id = int(result.originalIds[size_t(part)].size());
                    result.originalIds[size_t(part)].push_back(g[size_t(k)]);
                    if (visual) ++visualIds[size_t(part)];
                }
            }
    auto newId = [&](int p, int vertex) { return localId[size_t(slots.find(offset[size_t(p)] + vertex))]; };

    result.parts.resize(size_t(partCount));
    for (int part = 0; part < partCount; ++part) {
        geometry::PhysicalMesh& mesh = result.parts[size_t(part)];
        mesh.name = body.name;
        mesh.thickness = body.thickness;
        mesh.density = body.density;
        mesh.contactTolerance = body.contactTolerance;
        mesh.globalIdCount = int(result.originalIds[size_t(part)].size());
        for (int local = 0; local < visualIds[size_t(part)]; ++local)
            mesh.visual.positions.push_back(body.visual.positions[size_t(result.originalIds[size_t(part)][size_t(local)])]);
        for (int p : result.parents[size_t(part)]) mesh.mass += body.primitives[size_t(p)].massProperties(body.density);
    }

    // Faces go to the part of their primitives, each corner taking the new id of the first of
    // its primitives that carries it (they agree: the primitives of one face never part).
    const auto owners = faceOwners(body);
    std::vector<std::vector<int>> joined; // per primitive: its neighbours over unbroken connections
    auto idOf = [&](int p, int v) {
        const int k = vertexWithId(body.primitives[size_t(p)], v);
        return k >= 0 ? newId(p, k) : -1;
    };
    std::vector<int> faceInPart(body.visual.faces.size(), -1);
    const bool flags = !body.visual.crackFace.empty();
    for (int f = 0; f < int(body.visual.faces.size()); ++f) {
        const auto& own = owners[size_t(f)];
        geometry::PhysicalMesh& mesh = result.parts[size_t(partOf[size_t(own.front())])];
        std::vector<int> face;
        for (int v : body.visual.faces[size_t(f)]) {
            int id = -1;
            for (size_t o = 0; o < own.size() && id < 0; ++o) id = idOf(own[o], v);
            if (id < 0) {
                // A corner none of the face's primitives carries: a T-junction vertex that a
                // subdivision put into an uncut primitive's face where finer pieces meet its
                // edge (Subdivision.h); the pieces carry it. It takes the id of a piece still
                // connected to the face's primitives. Torn from all of them, the corner goes:
                // it lies on the straight edge, so the face keeps its shape, and the pieces'
                // own faces keep the vertex on their side of the opening.
                if (joined.empty()) {
                    joined.resize(count);
                    for (size_t c = 0; c < body.connections.size(); ++c) {
                        if (broken[c]) continue;
                        const auto [a, b] = body.connections[c];
                        joined[size_t(a)].push_back(b);
                        joined[size_t(b)].push_back(a);
                    }
                }
                for (size_t o = 0; o < own.size() && id < 0; ++o)
                    for (size_t j = 0; j < joined[size_t(own[o])].size() && id < 0; ++j) id = idOf(joined[size_t(own[o])][j], v);
                if (id < 0) continue;
            }
            face.push_back(id);
        }
        if (face.size() < 3)
            throw InputError("body '" + body.name + "': visual face " + std::to_string(f) + " has " +
                             std::to_string(face.size()) + " corners on its primitives and their neighbours, not 3");
        faceInPart[size_t(f)] = int(mesh.visual.faces.size());
        mesh.visual.faces.push_back(std::move(face));
        if (flags) mesh.visual.crackFace.push_back(body.visual.isCrackFace(size_t(f)));
    }
    for (int p = 0; p < n; ++p) {
        const int f = body.sourceFace[size_t(p)];
        result.parts[size_t(partOf[size_t(p)])].sourceFace.push_back(f < 0 ? -1 : faceInPart[size_t(f)]);
    }
    for (size_t c = 0; c < body.connections.size(); ++c) {
        if (broken[c]) continue;
        const auto [a, b] = body.connections[c];
        result.parts[size_t(partOf[size_t(a)])].connections.emplace_back(indexInPart[size_t(a)], indexInPart[size_t(b)]);
    }
    // Tear edges carried by one primitive of the part, in the part's ids.
    for (int p = 0; p < n && !body.tearEdges.empty(); ++p) {
        const auto& g = body.primitives[size_t(p)].globalIds();
        auto& edges = result.parts[size_t(partOf[size_t(p)])].tearEdges;
        for (int i = 0; i < int(g.size()); ++i)
            for (int j = i + 1; j < int(g.size()); ++j) {
                const std::pair<int, int> e(std::min(g[size_t(i)], g[size_t(j)]), std::max(g[size_t(i)], g[size_t(j)]));
                if (e.second >= visualCount || !std::binary_search(body.tearEdges.begin(), body.tearEdges.end(), e))
                    continue;
                const int a = newId(p, i), b = newId(p, j);
                edges.emplace_back(std::min(a, b), std::max(a, b));
            }
    }
    int originals = 0, total = 0;
    std::vector<char> seen(size_t(body.globalIdCount), 0);
    for (const auto& part : result.originalIds) {
        total += int(part.size());
        for (int id : part) originals += seen[size_t(id)] ? 0 : (seen[size_t(id)] = 1);
    }
    result.idsSplit = total - originals;
    // The primitives last: the faces and tear edges above read the body's.
    auto newIds = [&](int p) {
        std::vector<int> g(body.primitives[size_t(p)].globalIds().size());
        for (int k = 0; k < int(g.size()); ++k) g[size_t(k)] = newId(p, k);
        return g;
    };
    // Taken, the largest part keeps the body's vector, which is no longer needed: a new
    // vector of thousands of primitives is fresh pages in the frame of the tear.
    const int inPlace = take ? largestPart(result) : -1;
    for (int part = 0; part < partCount; ++part) {
        if (part == inPlace) continue;
        geometry::PhysicalMesh& mesh = result.parts[size_t(part)];
        mesh.primitives.reserve(result.parents[size_t(part)].size());
        for (int p : result.parents[size_t(part)]) {
            std::vector<int> g = newIds(p); // before the primitive moves
            if (take) {
                mesh.primitives.push_back(std::move((*take)[size_t(p)]));
                mesh.primitives.back().setGlobalIds(std::move(g));
            } else {
                mesh.primitives.push_back(body.primitives[size_t(p)].withGlobalIds(std::move(g)));
            }
        }
    }
    if (inPlace >= 0) {
        // Compacted in place: its primitives ascend, so each moves down onto a slot whose
        // primitive went to another part or already moved down.
        std::vector<geometry::ConvexPolyhedron>& all = *take;
        const std::vector<int>& parents = result.parents[size_t(inPlace)];
        for (size_t i = 0; i < parents.size(); ++i) {
            const size_t p = size_t(parents[i]);
            std::vector<int> g = newIds(int(p));
            if (p != i) all[i] = std::move(all[p]);
            all[i].setGlobalIds(std::move(g));
        }
        all.erase(all.begin() + std::ptrdiff_t(parents.size()), all.end());
        result.parts[size_t(inPlace)].primitives = std::move(all);
    }
    for (auto& mesh : result.parts) {
        std::sort(mesh.tearEdges.begin(), mesh.tearEdges.end());
        mesh.tearEdges.erase(std::unique(mesh.tearEdges.begin(), mesh.tearEdges.end()), mesh.tearEdges.end());
    }
    return result;
}

} // namespace

} // namespace shatter::fracture
