#include <shatter/plugin/fracture/BreakableConnections.h>

#include <algorithm>

namespace shatter::fracture {

namespace {

// Whether the visual ids two primitives share cross a tear line (see the header).
bool acrossTearLine(const std::vector<int>& shared, const std::vector<std::pair<int, int>>& tearEdges,
                    const std::vector<char>& onTearLine) {
    if (shared.empty()) return false;
    for (int v : shared)
        if (!onTearLine[size_t(v)]) return false;
    if (shared.size() == 1) return true;
    for (size_t i = 0; i < shared.size(); ++i)
        for (size_t j = i + 1; j < shared.size(); ++j) {
            const std::pair<int, int> e(std::min(shared[i], shared[j]), std::max(shared[i], shared[j]));
            if (std::binary_search(tearEdges.begin(), tearEdges.end(), e)) return true;
        }
    return false;
}

} // namespace

std::vector<std::pair<int, int>> sortedGlobalIds(const geometry::ConvexPolyhedron& p) {
    std::vector<std::pair<int, int>> out;
    const auto& ids = p.globalIds();
    for (int k = 0; k < int(ids.size()); ++k) out.emplace_back(ids[size_t(k)], k);
    std::sort(out.begin(), out.end());
    return out;
}

// A merge of the two sorted lists.
void sharedVertices(const std::vector<std::pair<int, int>>& a, const std::vector<std::pair<int, int>>& b,
                    std::vector<std::pair<int, int>>& out) {
    out.clear();
    size_t i = 0, j = 0;
    while (i < a.size() && j < b.size()) {
        if (a[i].first < b[j].first) ++i;
        else if (b[j].first < a[i].first) ++j;
        else out.emplace_back(a[i++].second, b[j++].second);
    }
}

namespace {

// What deciding whether a connection is breakable needs of the body, made once per call.
struct BreakableTest {
    const geometry::PhysicalMesh& body;
    bool everywhere;
    int visualCount;
    std::vector<char> onTearLine;

    BreakableTest(const geometry::PhysicalMesh& b, bool all)
        : body(b), everywhere(all), visualCount(int(b.visual.positions.size())), onTearLine(size_t(visualCount), 0) {
        for (const auto& [u, v] : body.tearEdges) onTearLine[size_t(u)] = onTearLine[size_t(v)] = 1;
    }

    // Appends connection c's entry to `out` when it is breakable (see the header); `idsOf(p)`
    // gives primitive p's sortedGlobalIds, asked only for connections that may be.
    template <class IdsOf>
    void test(int c, const IdsOf& idsOf, std::vector<BreakableConnection>& out) {
        const auto [a, b] = body.connections[size_t(c)];
        const int faceA = body.sourceFace[size_t(a)], faceB = body.sourceFace[size_t(b)];
        if (faceA >= 0 && faceA == faceB) return;
        // Along tear lines, a shares a vertex of a line with b: most primitives carry none.
        const auto& carried = body.primitives[size_t(a)].globalIds();
        if (!everywhere && std::none_of(carried.begin(), carried.end(),
                                        [&](int id) { return id < visualCount && onTearLine[size_t(id)]; }))
            return;
        sharedVertices(idsOf(a), idsOf(b), vertices);
        if (vertices.empty()) return;
        if (!everywhere) {
            sharedVisual.clear();
            for (const auto& [k, l] : vertices) {
                const int id = carried[size_t(k)];
                if (id < visualCount) sharedVisual.push_back(id);
            }
            if (!acrossTearLine(sharedVisual, body.tearEdges, onTearLine)) return;
        }
        out.push_back({c, a, b, vertices});
    }

private:
    std::vector<int> sharedVisual;                // scratch
    std::vector<std::pair<int, int>> vertices;    // scratch
};

// Each primitive's sortedGlobalIds, made when first asked for.
class SortedIds {
public:
    explicit SortedIds(const geometry::PhysicalMesh& body) : body_(body), ids_(body.primitives.size()) {}
    const std::vector<std::pair<int, int>>& operator()(int p) const {
        auto& ids = ids_[size_t(p)];
        if (ids.empty()) ids = sortedGlobalIds(body_.primitives[size_t(p)]);
        return ids;
    }

private:
    const geometry::PhysicalMesh& body_;
    mutable std::vector<std::vector<std::pair<int, int>>> ids_;
};

} // namespace

std::vector<BreakableConnection> breakableConnections(const geometry::PhysicalMesh& body, bool everywhere) {
    BreakableTest breakable(body, everywhere);
    const SortedIds ids(body);
    std::vector<BreakableConnection> out;
    for (int c = 0; c < int(body.connections.size()); ++c) breakable.test(c, ids, out);
    return out;
}

void updateBreakable(std::vector<BreakableConnection>& breakable, const geometry::PhysicalMesh& body,
                     const MeshOpening& opening, bool everywhere) {
    const size_t n = body.primitives.size();
    std::vector<char> touched(n, 0);
    for (int p : opening.touched) touched[size_t(p)] = 1;
    auto near = [&](int a, int b) { return touched[size_t(a)] || touched[size_t(b)]; };
    // The connections at a touched primitive, found again (in the order of the connections).
    BreakableTest test(body, everywhere);
    const SortedIds ids(body);
    std::vector<BreakableConnection> found;
    for (int c = 0; c < int(body.connections.size()); ++c)
        if (near(body.connections[size_t(c)].first, body.connections[size_t(c)].second)) test.test(c, ids, found);
    // The others keep their entries (the same vertices share the same ids), renumbered; both
    // lists are in the order of the connections.
    std::vector<BreakableConnection> out;
    out.reserve(breakable.size() + found.size());
    auto next = found.begin();
    for (BreakableConnection& entry : breakable) {
        const int c = opening.connectionIndex[size_t(entry.connection)];
        if (c < 0 || near(entry.a, entry.b)) continue;
        for (; next != found.end() && next->connection < c; ++next) out.push_back(std::move(*next));
        entry.connection = c;
        out.push_back(std::move(entry));
    }
    for (; next != found.end(); ++next) out.push_back(std::move(*next));
    breakable = std::move(out);
}

std::vector<int> stretchedConnections(std::span<const BreakableConnection> breakable,
                                      const std::vector<geometry::ConvexPolyhedron>& primitives,
                                      std::span<const Eigen::Isometry3d> poses, double distance) {
    // Each primitive's vertices are placed once, and only for primitives of a breakable
    // connection: a vertex is shared by several connections (a quad prism's corner by three),
    // and along a tear line most primitives have none.
    std::vector<int> first(primitives.size(), -1);
    std::vector<Eigen::Vector3d> placed;
    auto vertexOf = [&](int p, int k) -> Eigen::Vector3d {
        int& start = first[size_t(p)];
        if (start < 0) {
            start = int(placed.size());
            for (const auto& v : primitives[size_t(p)].vertices()) placed.push_back(poses[size_t(p)] * v);
        }
        return placed[size_t(start + k)];
    };
    const double limit = distance * distance;
    std::vector<int> out;
    for (int c = 0; c < int(breakable.size()); ++c) {
        const BreakableConnection& connection = breakable[size_t(c)];
        for (const auto& [k, l] : connection.vertices)
            if ((vertexOf(connection.a, k) - vertexOf(connection.b, l)).squaredNorm() > limit) {
                out.push_back(c);
                break;
            }
    }
    return out;
}

} // namespace shatter::fracture
