#include <shatter/plugin/fracture/FractureMesh.h>

#include <shatter/plugin/common/Prefetch.h>
#include <shatter/plugin/common/SettingCheck.h>
#include <shatter/plugin/fracture/FragmentSurface.h>
#include <shatter/plugin/fracture/NewVertexIds.h>
#include <shatter/plugin/fracture/SolidSplitter.h>
#include <shatter/plugin/geometry/AabbTree.h>
#include <shatter/plugin/geometry/Connectivity.h>
#include <shatter/plugin/geometry/UnionFind.h>

#include <algorithm>
#include <bit>
#include <cstdint>
#include <chrono>
#include <deque>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <numeric>
#include <optional>
#include <span>

namespace shatter::fracture {

void CutSettings::check(const std::string& body) const {
    requirePositive(body, "minimum piece size", minimumPieceSize);
    requirePositive(body, "snap tolerance", snapTolerance);
    requireSetting(snapTolerance < minimumPieceSize, body, "snap tolerance", "below the minimum piece size",
                   snapTolerance);
}

namespace {

// A cell within the radius, placed in the body's rest coordinates.
struct PlacedCell {
    int cell = 0;
    std::vector<geometry::Plane> planes; // outward
    // Per plane: 2 × pattern plane + (1 when its normal is the pattern plane's negated), or -1
    // when no other cell has the plane. The neighbour across has this key ^ 1.
    std::vector<int> keys;
    std::vector<int> across; // per plane: the pattern cell on its other side, kManyCells, or -1
    geometry::Aabb box;
};

// PlacedCell::across of a plane that more than two cells have (a grid's or glass pattern's).
constexpr int kManyCells = -2;

// A ball holding a primitive's vertices, for a quick side-of-plane test.
struct Ball {
    Eigen::Vector3d centre;
    double radius = 0.0;
    // The box itself, for a plane the ball straddles: its half extents, and the margin that its
    // reach along a normal is raised by (as the radius is).
    Eigen::Vector3d half = Eigen::Vector3d::Zero();
    double margin = 0.0;
};
// The box's circumscribed ball, its radius raised so that round-off in a plane distance
// (relative 1e-16 of the coordinates) cannot put a vertex outside it.
Ball ballAround(const geometry::Aabb& box) {
    const Eigen::Vector3d centre = 0.5 * (box.min + box.max);
    const double scale = box.min.cwiseAbs().cwiseMax(box.max.cwiseAbs()).maxCoeff();
    const double margin = 1e-12 * (1.0 + scale);
    return {centre, 0.5 * box.diagonal() * (1.0 + 1e-9) + margin, 0.5 * (box.max - box.min) * (1.0 + 1e-9), margin};
}

// Boxes (the free cells') by bucket of a regular grid over their joint bounds, each bucket's
// list in box order. The boxes overlapping a query box come from the one or few buckets it
// reaches: a primitive of a large body asks this about twelve thousand times per break, where
// a tree walk with a std::function call per visit cost about a third more (callgrind).
class BoxGrid {
public:
    static constexpr int kSize = 16; // buckets per axis

    BoxGrid() = default;
    BoxGrid(const std::vector<geometry::Aabb>& boxes, const geometry::Aabb& bounds)
        : boxes_(boxes), origin_(bounds.min),
          scale_(bucketsPerMetre(bounds.extent())),
          start_(size_t(kSize * kSize * kSize) + 1, 0) {
        // Counts, then offsets, then the lists (filled in box order, so each is ascending).
        forEachBucket([&](int b, int) { ++start_[size_t(b) + 1]; });
        for (size_t b = 1; b < start_.size(); ++b) start_[b] += start_[b - 1];
        std::vector<int> fill(start_.begin(), start_.end() - 1);
        entries_.resize(size_t(start_.back()));
        forEachBucket([&](int b, int box) { entries_[size_t(fill[size_t(b)]++)] = box; });
    }

    // The boxes overlapping `box` (Aabb::overlaps), ascending, into `out` (cleared first).
    void overlapping(const geometry::Aabb& box, std::vector<int>& out) const {
        out.clear();
        const Eigen::Array3i lo = bucketOf(box.min), hi = bucketOf(box.max);
        for (int z = lo.z(); z <= hi.z(); ++z)
            for (int y = lo.y(); y <= hi.y(); ++y)
                for (int x = lo.x(); x <= hi.x(); ++x) {
                    const int b = (z * kSize + y) * kSize + x;
                    for (int k = start_[size_t(b)]; k < start_[size_t(b) + 1]; ++k)
                        if (const int c = entries_[size_t(k)]; boxes_[size_t(c)].overlaps(box)) out.push_back(c);
                }
        if (out.size() > 1 && (lo != hi).any()) { // a box in several buckets is listed in each
            std::sort(out.begin(), out.end());
            out.erase(std::unique(out.begin(), out.end()), out.end());
        }
    }

private:
    // kSize buckets over each axis's extent; an axis without extent (or one so small that the
    // quotient overflows) is one bucket: its scale is 0, or its products are 0·∞ = NaN, which
    // bucketOf sends to bucket 0.
    static Eigen::Vector3d bucketsPerMetre(const Eigen::Vector3d& extent) {
        Eigen::Vector3d scale;
        for (int k = 0; k < 3; ++k) scale[k] = extent[k] > 0.0 ? double(kSize) / extent[k] : 0.0;
        return scale;
    }
    // The bucket holding point p, clamped to the grid: monotone in p, so two overlapping
    // boxes share the bucket of any point they share. (Clamped first, so truncation floors;
    // the comparisons are false for NaN, which goes to 0, never to int(NaN).)
    Eigen::Array3i bucketOf(const Eigen::Vector3d& p) const {
        Eigen::Array3i b;
        for (int k = 0; k < 3; ++k) {
            const double v = (p[k] - origin_[k]) * scale_[k];
            b[k] = v >= double(kSize - 1) ? kSize - 1 : v > 0.0 ? int(v) : 0;
        }
        return b;
    }
    template <typename Visit>
    void forEachBucket(const Visit& visit) const { // visit(bucket, box) for every bucket a box reaches
        for (int c = 0; c < int(boxes_.size()); ++c) {
            const Eigen::Array3i lo = bucketOf(boxes_[size_t(c)].min), hi = bucketOf(boxes_[size_t(c)].max);
            for (int z = lo.z(); z <= hi.z(); ++z)
                for (int y = lo.y(); y <= hi.y(); ++y)
                    for (int x = lo.x(); x <= hi.x(); ++x) visit((z * kSize + y) * kSize + x, c);
        }
    }

    std::vector<geometry::Aabb> boxes_;
    Eigen::Vector3d origin_ = Eigen::Vector3d::Zero();
    Eigen::Vector3d scale_ = Eigen::Vector3d::Ones(); // buckets per metre on each axis
    std::vector<int> start_;   // bucket b lists entries_[start_[b] .. start_[b + 1])
    std::vector<int> entries_; // box indices
};

struct Piece {
    int parent = 0;  // body primitive
    int region = 0;  // placed cell, or the far region (= number of placed cells)
    int solid = -1;  // index of the cut piece (shapes_, cutFaces_), or -1 when the primitive moved whole
};

// `from` into `to` (as large) ordered by key(p) in [0, n), stably, by counting.
template <typename Key>
void countingPass(const std::vector<std::pair<int, int>>& from, std::vector<std::pair<int, int>>& to, int n,
                  std::vector<int>& count, const Key& key) {
    count.assign(size_t(n) + 1, 0);
    for (const auto& p : from) ++count[size_t(key(p)) + 1];
    for (int i = 0; i < n; ++i) count[size_t(i) + 1] += count[size_t(i)];
    for (const auto& p : from) to[size_t(count[size_t(key(p))]++)] = p;
}

// Sorts pairs (a < b, both below n) and drops repeats in O(pairs + n): two stable counting
// passes, by b and then by a, through `scratch` (kept between calls). A fragment has tens to
// tens of thousands of connections; a comparison sort of a large one cost more than all the
// cutting, and a counting pass by a then a std::sort per a's bucket (a call per primitive)
// ~1 M instructions in five events of the 16k shell.
void sortPairs(std::vector<std::pair<int, int>>& pairs, int n, std::vector<int>& count,
               std::vector<std::pair<int, int>>& scratch) {
    scratch.resize(pairs.size());
    countingPass(pairs, scratch, n, count, [](const std::pair<int, int>& p) { return p.second; });
    countingPass(scratch, pairs, n, count, [](const std::pair<int, int>& p) { return p.first; });
    pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
}

// Calls visit(i) for every i with marks[i] != 0, ascending, reading the marks 8 at a time: a
// break marks a few hundred of a large body's ~16,000 primitives (or inner ids), and a test per
// mark was ~0.1 M instructions a pass. visit may clear marks[i] (and no other mark).
template <typename Visit>
void forEachMarked(const std::vector<char>& marks, const Visit& visit) {
    const size_t n = marks.size(), inWords = n & ~size_t(7);
    for (size_t i = 0; i < inWords; i += 8) {
        std::uint64_t word;
        std::memcpy(&word, marks.data() + i, sizeof word);
        if (word == 0) continue;
        for (size_t k = i; k < i + 8; ++k)
            if (marks[k]) visit(int(k));
    }
    for (size_t k = inWords; k < n; ++k)
        if (marks[k]) visit(int(k));
}

// How many values of `sorted` (ascending) are below v: std::lower_bound's distance, without
// its branch per step, taken half the time at random (not measured apart: part of asm16c's
// remainderEdit pass, 10.04 -> 9.15 M instructions over five 16k-shell events).
int countBelow(const std::vector<int>& sorted, int v) {
    const int* first = sorted.data();
    size_t n = sorted.size();
    while (n > 1) {
        const size_t half = n / 2;
        first = first[half] < v ? first + half : first;
        n -= half;
    }
    return int(first - sorted.data()) + (n == 1 && *first < v);
}

// buildFragment's maps, kept by the thread from one event to the next: filled with -1 at each
// event they cost ~1.06 M instructions in five breaks of the 16k shell. They are -1 everywhere
// between fragments (Unset), so they give the same results whichever event used them last.
struct FragmentMaps {
    std::vector<int> localOf;    // fracture-wide id -> id in the fragment being built, or -1
    std::vector<int> localPiece; // piece -> index in the fragment being built, or -1
    std::vector<int> idOrder;    // the fragment's ids in order of first use (room for every id)
};
FragmentMaps& fragmentMaps() {
    thread_local FragmentMaps maps;
    return maps;
}
// Room for keys [0, n) in a map of FragmentMaps, the new ones -1.
void makeRoom(std::vector<int>& map, size_t n) {
    if (map.size() < n) map.resize(n, -1);
}
// Sets map[k] back to -1 for the keys[0, count) when it goes out of scope, also through an
// exception. (A stamp per entry instead, checked on every look-up, cost +1.3 M instructions.)
struct Unset {
    std::vector<int>& map;
    const int* keys;
    const int& count;
    ~Unset() {
        for (int k = 0; k < count; ++k) map[size_t(keys[k])] = -1;
    }
};

// What uniteWholeFar's loop did: how many connections it listed as touched, and whether the
// connections came sorted by their first primitive.
struct FarUnions {
    size_t listed = 0;
    bool sorted = true;
};

// uniteWholeFar's loop over the body's connections: unites the ends of those between two whole
// far primitives in `up` (a union-find over the primitives, -1 for those not whole far) and lists
// the others' indices in `touched`.
FarUnions uniteAlong(const std::pair<int, int>* connections, size_t count, int* up, int* touched) {
    FarUnions done;
    auto find = [up](int p) { // path halving, as UnionFind's
        while (up[p] != p) {
            up[p] = up[up[p]];
            p = up[p];
        }
        return p;
    };
    // A primitive's connections mostly come one after another (sorted by their first
    // primitive, but for those a rest edit appended): the root of its island is kept from
    // one to the next (a union keeps the smaller root).
    int current = -1, root = -1; // the whole far primitive whose island root is `root`
    for (size_t c = 0; c < count; ++c) {
        const int a = connections[c].first;
        // b unsigned (ends are >= 0): its 32-bit load is the index as it is, with no sign
        // extension or address kept, so the most common connection, into root's island
        // already, takes 11 instructions, not 12.
        const size_t b = unsigned(connections[c].second);
        if (a != current) {
            if (c > 0 && a < connections[c - 1].first) done.sorted = false;
            if (up[a] < 0) {
                touched[done.listed++] = int(c);
                current = -1; // the next connection's order is checked against this one
                continue;
            }
            root = find(a);
            current = a;
        }
        const int upB = up[b];
        if (upB == root) continue; // joined already (most are): no find
        if (upB < 0) {
            touched[done.listed++] = int(c);
            continue;
        }
        const int other = find(int(b));
        if (other == root) continue;
        if (other < root) { // the larger root hangs under the smaller, as UnionFind::unite
            up[root] = other;
            root = other;
        } else {
            up[other] = root;
        }
    }
    return done;
}

// The phases are kept out of line ([[gnu::noinline]]) so that an instruction profile of an
// event (callgrind) splits it the way FractureResult::seconds does.
class Fracturer {
public:
    Fracturer(const geometry::PhysicalMesh& body, const FracturePattern& pattern, const Placement& where,
              const CutSettings& settings, const PrimitiveIndex& index = {})
        : body_(body), pattern_(pattern), where_(where), settings_(settings), index_(index),
          ids_(body.globalIdCount, settings.snapTolerance) {}

    FractureResult run() {
        using Clock = std::chrono::steady_clock;
        const auto t0 = Clock::now();
        placeCells();
        const auto t1 = Clock::now();
        surface_.emplace(body_, index_.surface); // the kinds of the faces of cut primitives
        cutPrimitives();
        const auto t2 = Clock::now();
        const bool nothingFree = untouched();
        std::vector<std::vector<int>> fragments;
        if (!nothingFree) {
            findIslands();
            fragments = mergeSmallIslands();
        }
        const auto t3 = Clock::now();
        FractureResult result = nothingFree ? wholeBody() : assemble(std::move(fragments));
        const auto t4 = Clock::now();
        auto seconds = [](auto a, auto b) { return std::chrono::duration<double>(b - a).count(); };
        result.seconds = {seconds(t0, t1), seconds(t1, t2), seconds(t2, t3), seconds(t3, t4)};
        return result;
    }

    CutPieces cutOnly() {
        const auto t0 = std::chrono::steady_clock::now();
        placeCells();
        cutPrimitives();
        CutPieces result;
        result.primitivesCut = int(cutList_.size());
        for (const Piece& p : pieces_) {
            result.parents.push_back(p.parent);
            result.clipped.push_back(p.solid >= 0);
        }
        result.shapes = std::move(shapes_); // in piece order
        result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        return result;
    }

private:
    int far() const { return int(cells_.size()); }
    const geometry::ConvexPolyhedron& shape(int piece) const {
        const Piece& p = pieces_[size_t(piece)];
        return p.solid < 0 ? body_.primitives[size_t(p.parent)] : shapes_[size_t(p.solid)];
    }
    double volume(int piece) const { return shape(piece).volume(); }
    // The piece's shape with fragment ids, for the one fragment it goes to: a primitive moved
    // whole keeps its geometry bit for bit (a copy of the body's); a cut piece's shape is
    // moved out (shape(piece) is not asked for again) and its ids written over its own (a new
    // vector, and the old one freed, was an allocation and a free per cut piece: ~1.1k a
    // 64-cell break of the 16k shell).
    geometry::ConvexPolyhedron takeShape(int piece, std::span<const int> ids) {
        const Piece& p = pieces_[size_t(piece)];
        if (p.solid < 0)
            return body_.primitives[size_t(p.parent)].withGlobalIds(std::vector<int>(ids.begin(), ids.end()));
        geometry::ConvexPolyhedron out = std::move(shapes_[size_t(p.solid)]);
        out.overwriteGlobalIds(ids);
        return out;
    }
    // The first n values of pieceIds_, grown to hold them: a piece's ids mapped to the
    // fragment's (takeShape copies them).
    std::span<int> pieceIds(size_t n) {
        if (pieceIds_.size() < n) pieceIds_.resize(n);
        return {pieceIds_.data(), n};
    }

    // Cells within the radius cut pieces free (cells_); the others (outerCells_) only split
    // what a free cell cut off a primitive into convex parts that stay with the rest.
    [[gnu::noinline]] void placeCells() {
        rotation_ = where_.rotation();
        placedPlane_.assign(pattern_.planes.size(), -1);
        cellsOfPlane_.assign(pattern_.planes.size(), {});
        for (size_t c = 0; c < pattern_.cellFaces.size(); ++c)
            for (const CellFace& face : pattern_.cellFaces[c]) {
                CellsOfPlane& cells = cellsOfPlane_[size_t(face.plane)];
                if (cells.count < 2) cells.cell[cells.count] = int(c);
                ++cells.count;
            }
        for (size_t c = 0; c < pattern_.cells.size(); ++c) {
            const bool free = pattern_.centres[c].norm() <= pattern_.radius;
            PlacedCell cell = place(int(c));
            if (free) cellBounds_.extend(cell.box);
            (free ? cells_ : outerCells_).push_back(std::move(cell));
        }
        // The order cutPrimitive clips to cells in: free cells, then outer cells, each ascending.
        clipRank_.assign(pattern_.cells.size(), 0);
        cellBox_.assign(pattern_.cells.size(), {});
        for (size_t k = 0; k < cells_.size(); ++k) {
            clipRank_[size_t(cells_[k].cell)] = int(k);
            cellBox_[size_t(cells_[k].cell)] = cells_[k].box;
        }
        for (size_t k = 0; k < outerCells_.size(); ++k) {
            clipRank_[size_t(outerCells_[k].cell)] = int(cells_.size() + k);
            cellBox_[size_t(outerCells_[k].cell)] = outerCells_[k].box;
        }
        std::vector<geometry::Aabb> boxes;
        for (const auto& c : cells_) boxes.push_back(c.box);
        if (!boxes.empty()) grid_ = BoxGrid(boxes, cellBounds_);
        boxes.clear();
        for (const auto& c : outerCells_) boxes.push_back(c.box);
        if (!boxes.empty()) outerTree_ = geometry::AabbTree(boxes);
        // Every cell is placed, so every plane of the domain is.
        for (const CellFace& face : pattern_.domain) {
            const auto& p = planes_[size_t(placedPlane_[size_t(face.plane)])];
            domain_.planes.push_back({face.sign * p.normal, face.sign * p.offset});
        }
    }

    PlacedCell place(int c) {
        PlacedCell cell;
        cell.cell = c;
        for (const auto& face : pattern_.cellFaces[size_t(c)]) {
            int& k = placedPlane_[size_t(face.plane)];
            if (k < 0) {
                // n·x = d in the pattern ⇒ (Rn)·y = scale·d + (Rn)·point in the body.
                const auto& p = pattern_.planes[size_t(face.plane)];
                const Eigen::Vector3d n = rotation_ * p.normal;
                k = int(planes_.size());
                planes_.push_back({n, where_.scale * p.offset + n.dot(where_.point)});
            }
            // Negation is exact: the neighbour across this face cuts along the same bits.
            const auto& p = planes_[size_t(k)];
            cell.planes.push_back({face.sign * p.normal, face.sign * p.offset});
            const CellsOfPlane& cells = cellsOfPlane_[size_t(face.plane)];
            cell.keys.push_back(cells.count >= 2 ? 2 * face.plane + (face.sign < 0.0) : -1);
            cell.across.push_back(cells.count == 2 ? cells.cell[cells.cell[0] == c ? 1 : 0]
                                                   : (cells.count > 2 ? kManyCells : -1));
        }
        for (const auto& v : pattern_.cells[size_t(c)].vertices())
            cell.box.extend(where_.point + where_.scale * (rotation_ * v));
        cell.box = cell.box.inflated(settings_.snapTolerance);
        return cell;
    }

    [[gnu::noinline]] void cutPrimitives() {
        const int count = int(body_.primitives.size());
        firstPiece_.resize(size_t(count) + 1);
        wholeFar_.resize(size_t(count));
        pieces_.reserve(size_t(count) + 1); // one piece per primitive, and a few more
        if (index_.tree && !index_.tree->empty() && !cells_.empty()) {
            cellsReachingByTree();
            // At most a piece per cell reaching a primitive (and the rest's few): room for them
            // at once, as grown by push_back the cut pieces were moved (~350 B each, ~1,100 a
            // break of the 16k shell) into fresh pages at every doubling. Unused room is
            // address space only.
            shapes_.reserve(reach_.size() + reach_.size() / 4);
            // Most primitives no cell reaches, in long runs: each run before a reached primitive
            // kept whole at once. The next reached primitives are asked for ahead (prefetchReached).
            int p = 0;
            for (size_t k = 0; k < reached_.size(); ++k) {
                const int q = reached_[k];
                keepWhole(p, q);
                prefetchReached(k);
                piecesOf(q, std::span<const int>(reach_.data() + reachStart_[k], reach_.data() + reachStart_[k + 1]));
                p = q + 1;
            }
            keepWhole(p, count);
        } else {
            std::vector<int> candidates;
            for (int p = 0; p < count; ++p) {
                const auto& box = body_.primitives[size_t(p)].bounds();
                candidates.clear();
                if (!cells_.empty() && box.overlaps(cellBounds_)) grid_.overlapping(box, candidates);
                piecesOf(p, candidates);
            }
        }
        firstPiece_[size_t(count)] = int(pieces_.size());
    }

    // The reached primitives' data lie apart in memory and are mostly out of cache when their
    // turn comes (the 16k shell's are ~10 MB; a cache simulation put ~6.5 k misses of the last
    // level a break on them: the vertices clipToCell reads, the ids and faces original()
    // copies). Each step asks for them in stages, a level of indirection per step: the
    // primitive three ahead (its vectors' addresses), the vertices, ids and face list two
    // ahead, the face indices one ahead. Timing only (the pieces do not depend on it): with the
    // leaves' boxes below, cpu_ms of a 64-cell break of the 16k shell -2.8 % (median of 30
    // interleaved runs; clipToCell's share of the time profile 20 -> 17 %), for ~15 k more
    // instructions a break.
    [[gnu::always_inline]] void prefetchReached(size_t k) const { // hints alone: see Prefetch.h
        const size_t count = reached_.size();
        if (k + 3 < count) prefetchRange(&body_.primitives[size_t(reached_[k + 3])], sizeof(geometry::ConvexPolyhedron));
        if (k + 2 < count) {
            const geometry::ConvexPolyhedron& primitive = body_.primitives[size_t(reached_[k + 2])];
            prefetchRange(primitive.vertices().data(), primitive.vertices().size() * sizeof(Eigen::Vector3d));
            prefetchRange(primitive.globalIds().data(), primitive.globalIds().size() * sizeof(int));
            prefetchRange(&primitive.faces(), sizeof(geometry::FaceList));
        }
        if (k + 1 < count) {
            const geometry::FaceList& faces = body_.primitives[size_t(reached_[k + 1])].faces();
            prefetchRange(faces.indices().data(), faces.indices().size() * sizeof(int));
        }
    }

    // Primitive p's pieces, given the free cells that may reach it (ascending): the whole
    // primitive in the far region when there are none, else what cutPrimitive makes of it.
    void piecesOf(int p, std::span<const int> cells) {
        if (cells.empty()) {
            keepWhole(p, p + 1);
            return;
        }
        const int first = int(pieces_.size());
        firstPiece_[size_t(p)] = first;
        cutPrimitive(p, cells);
        const Piece& q = pieces_[size_t(first)];
        wholeFar_[size_t(p)] = q.solid < 0 && q.region == far() ? first : -1;
    }

    // Primitives [begin, end) stay whole in the far region: a piece each.
    void keepWhole(int begin, int end) {
        const int first = int(pieces_.size());
        pieces_.resize(pieces_.size() + size_t(end - begin));
        for (int p = begin; p < end; ++p) {
            const int piece = first + (p - begin);
            pieces_[size_t(piece)] = {p, far(), -1};
            firstPiece_[size_t(p)] = piece;
            wholeFar_[size_t(p)] = piece;
        }
    }

    // What a cell leaves of primitive p: nothing, the whole primitive, or a part (in scratch
    // space, valid until the next clip).
    struct Clip {
        enum Kind { Nothing, Whole, Part } kind = Nothing;
        const Solid* part = nullptr;
    };
    // Clips primitive p (within the ball `bound`) to the cell. Its solid (original_) is made
    // only once a plane of some cell cuts it: most primitives lie inside one cell.
    Clip clipToCell(int p, const Ball& bound, const PlacedCell& cell) {
        const auto& vertices = body_.primitives[size_t(p)].vertices();
        // Planes with none of the solid's vertices beyond them cannot cut any part of it (its
        // parts lie in its hull): one pass of dot products finds the few planes that need a split.
        // A plane farther than the ball's radius from its centre has every vertex on one side.
        const double tolerance = settings_.snapTolerance;
        cutting_.clear();
        for (const auto& plane : cell.planes) {
            const double centre = plane.normal.dot(bound.centre) - plane.offset;
            if (centre + bound.radius < -tolerance) continue;       // wholly below
            if (centre - bound.radius > tolerance) return {}; // wholly above
            // The box reaches |n|·half along the normal, less than the ball's radius unless n
            // runs along its diagonal: a thin primitive's box settles a good part of the planes
            // its ball straddles, without the pass over its vertices.
            const double reach = plane.normal.cwiseAbs().dot(bound.half) + bound.margin;
            if (centre + reach < -tolerance) continue;
            if (centre - reach > tolerance) return {};
            int above = 0;
            bool below = false;
            for (const auto& v : vertices) {
                const double s = plane.normal.dot(v) - plane.offset;
                above += s > tolerance;
                below |= s < -tolerance;
            }
            if (above == 0) continue;
            if (!below) return {}; // wholly outside this face of the cell
            // The planes that cut off the most vertices first: what they remove, later planes
            // need not split again (a later plane then finds nothing above it, and split returns
            // after its distance pass). Inserted in place after those cutting off as many or
            // more, so ties keep the cell's face order (deterministic): the order the
            // std::stable_sort this replaces gave, without its buffer's allocation per clip
            // (~2 M instructions of the five events, a few planes a clip).
            cutting_.push_back({above, int(&plane - cell.planes.data())});
            for (size_t k = cutting_.size() - 1; k > 0 && cutting_[k - 1].first < above; --k)
                std::swap(cutting_[k - 1], cutting_[k]);
        }
        if (cutting_.empty()) return {Clip::Whole};
        const Solid& solid = original(p);
        const Solid* current = &solid;
        // A neighbour across one of these planes that split the primitive by it first kept the
        // other side (sides_): that side is where this cell starts, one split fewer.
        size_t next = 0;
        for (size_t j = 0; j < cutting_.size() && next == 0; ++j) {
            const int across = cell.keys[size_t(cutting_[j].second)] ^ 1;
            for (int k = 0; k < sideCount_; ++k)
                if (sideKeys_[size_t(k)] == across) {
                    std::rotate(cutting_.begin(), cutting_.begin() + std::ptrdiff_t(j),
                                cutting_.begin() + std::ptrdiff_t(j) + 1);
                    current = &sides_[size_t(k)];
                    next = 1;
                    break;
                }
        }
        for (; next < cutting_.size(); ++next) {
            const int index = cutting_[next].second;
            const geometry::Plane& plane = cell.planes[size_t(index)];
            Solid& target = current == &scratch_[0] ? scratch_[1] : scratch_[0];
            // The first split of the primitive by a plane another cell has keeps the side
            // beyond it for that cell (the same crossings, computed and looked up once).
            const int across = cell.across[size_t(index)];
            // Only when the neighbour across comes later and may reach the primitive.
            const bool keep = current == &solid &&
                              (across == kManyCells ||
                               (across >= 0 && clipRank_[size_t(across)] > clipRank_[size_t(cell.cell)] &&
                                cellBox_[size_t(across)].overlaps(body_.primitives[size_t(p)].bounds())));
            if (keep && sideCount_ == int(sides_.size())) {
                sides_.emplace_back();
                sideKeys_.push_back(-1);
            }
            const auto outcome = splitter_.split(*current, plane.normal, plane.offset, tolerance, ids_, target,
                                                 keep ? &sides_[size_t(sideCount_)] : nullptr);
            if (keep && outcome == SolidSplitter::Outcome::Split) sideKeys_[size_t(sideCount_++)] = cell.keys[size_t(index)];
            if (outcome == SolidSplitter::Outcome::Above) return {};
            if (outcome == SolidSplitter::Outcome::Split) current = &target;
        }
        return current == &solid ? Clip{Clip::Whole} : Clip{Clip::Part, current};
    }

    const Solid& original(int p) {
        if (originalOf_ != p) {
            const auto& primitive = body_.primitives[size_t(p)];
            if (!surface_) { // cutMesh: kinds from the ids alone (it needs none)
                solidOfPrimitive(primitive, int(body_.visual.positions.size()), original_);
            } else { // what each face shows, from the body's faces
                shapeOfPrimitive(primitive, original_);
                std::vector<int>& ids = faceIds_;
                for (size_t f = 0; f < primitive.faces().size(); ++f) {
                    ids.clear();
                    for (int v : primitive.faces()[f]) ids.push_back(primitive.globalIds()[size_t(v)]);
                    original_.kinds[f] = surface_->kindOf(p, ids);
                }
            }
            originalOf_ = p;
        }
        return original_;
    }

    // Inlined, as it was before it kept cutPieces_ (+0.1 M instructions out of line).
    [[gnu::always_inline]] void addCutPiece(int parent, int region, const Solid& solid) {
        shapes_.push_back(polyhedronOf(solid));
        cutPieces_.push_back(int(pieces_.size()));
        pieces_.push_back({parent, region, cutFaces_.add(solid)});
    }

    // Per primitive, the free cells that may reach it (reached_/reachStart_/reach_, each list ascending),
    // found from the body's index instead of each primitive's box: the cells whose box
    // overlaps the primitive's (what the grid gives), less those with a plane that every
    // vertex of the primitive lies beyond (clipToCell would find Nothing of it there, before
    // any split). The tree is searched per cell with the cell's planes moved into its frame:
    // a subtree is left at the first box that lies beyond one of them by the snap tolerance
    // and a margin far above round-off (of the planes' move and of the tree's boxes), so that
    // none of its primitives' vertices can be within the tolerance however they are computed.
    void cellsReachingByTree() {
        const Eigen::Isometry3d& toMesh = index_.treeToMesh;
        const geometry::Aabb all = geometry::transformedAabb(index_.tree->bounds(), toMesh);
        const double scale = std::max({all.min.cwiseAbs().maxCoeff(), all.max.cwiseAbs().maxCoeff(),
                                       cellBounds_.min.cwiseAbs().maxCoeff(), cellBounds_.max.cwiseAbs().maxCoeff(),
                                       toMesh.translation().cwiseAbs().maxCoeff()});
        const double margin = 1e-9 * (1.0 + scale);
        const double beyond = settings_.snapTolerance + margin;
        std::vector<std::pair<int, int>> pairs; // (primitive, cell), by cell
        // The cell's planes in the tree's frame, with |n| for a box's reach along n.
        struct TreePlane {
            Eigen::Vector3d normal, absNormal;
            double offset;
        };
        std::vector<TreePlane> planes;
        for (int c = 0; c < int(cells_.size()); ++c) {
            const PlacedCell& cell = cells_[size_t(c)];
            // n·x - d with x = A y + b is (Aᵀn)·y - (d - n·b).
            planes.clear();
            for (const auto& plane : cell.planes) {
                const Eigen::Vector3d n = toMesh.linear().transpose() * plane.normal;
                planes.push_back({n, n.cwiseAbs(), plane.offset - plane.normal.dot(toMesh.translation())});
            }
            int last = 0; // the plane that left the last subtree out: its neighbours tend to lie beyond it too
            // Per box, the planes it still straddles (a bit each): a box wholly on the inner
            // side of a plane holds boxes that are too, which that plane never leaves out.
            // Distances from the box's centre ± its reach (round-off far below the margin).
            const auto reaches = [&](const geometry::Aabb& box, std::uint64_t& open) {
                const Eigen::Vector3d centre = 0.5 * (box.min + box.max), half = 0.5 * (box.max - box.min);
                const auto distance = [&](const TreePlane& plane) { return plane.normal.dot(centre) - plane.offset; };
                if (open >> last & 1) {
                    const TreePlane& plane = planes[size_t(last)];
                    if (distance(plane) - plane.absNormal.dot(half) > beyond) return false;
                }
                for (std::uint64_t bits = open; bits != 0; bits &= bits - 1) {
                    const int j = std::countr_zero(bits);
                    const TreePlane& plane = planes[size_t(j)];
                    const double d = distance(plane), reach = plane.absNormal.dot(half);
                    if (d - reach > beyond) {
                        last = j;
                        return false;
                    }
                    if (d + reach < -beyond) open &= ~(std::uint64_t(1) << j);
                }
                return true;
            };
            // (Planes past the 64th of a cell are left out of the test: fewer subtrees skipped.)
            const std::uint64_t every = planes.size() >= 64 ? ~std::uint64_t(0) : (std::uint64_t(1) << planes.size()) - 1;
            leaves_.clear();
            index_.tree->search(every, reaches, [&](int p) { leaves_.push_back(p); });
            pairLeavesWith(c, cell.box, pairs);
        }
        listReached(pairs);
    }

    // The leaves (of one cell's tree walk) whose primitive's box overlaps the cell's box, as
    // (primitive, cell) pairs. The walk first, the boxes after: they lie apart in memory and
    // mostly out of cache (~1-2 k a break of the 16k shell), so each is asked for kAhead
    // leaves before it is read and their misses overlap (cut16c: with the primitives'
    // prefetch in cutPrimitives, cpu_ms of a 64-cell break of the 16k shell -2.8 %).
    void pairLeavesWith(int c, const geometry::Aabb& box, std::vector<std::pair<int, int>>& pairs) const {
        constexpr size_t kAhead = 16;
        const size_t n = leaves_.size();
        const auto& primitives = body_.primitives;
        for (size_t k = 0; k < std::min(n, kAhead); ++k)
            prefetchRange(&primitives[size_t(leaves_[k])].bounds(), sizeof(geometry::Aabb));
        for (size_t k = 0; k < n; ++k) {
            if (k + kAhead < n) prefetchRange(&primitives[size_t(leaves_[k + kAhead])].bounds(), sizeof(geometry::Aabb));
            if (primitives[size_t(leaves_[k])].bounds().overlaps(box)) pairs.emplace_back(leaves_[k], c);
        }
    }

    // reached_, reachStart_ and reach_ from the (primitive, cell) pairs: by primitive, in cell
    // order within each (a primitive is a leaf once per cell's walk). A sort of the ~1-2 k
    // pairs, where a counting sort by primitive wrote and read three arrays of a value per
    // primitive (16k) a break.
    void listReached(std::vector<std::pair<int, int>>& pairs) {
        std::sort(pairs.begin(), pairs.end());
        reached_.clear();
        reachStart_.clear();
        reach_.resize(pairs.size());
        for (size_t k = 0; k < pairs.size(); ++k) {
            if (k == 0 || pairs[k].first != pairs[k - 1].first) {
                reached_.push_back(pairs[k].first);
                reachStart_.push_back(int(k));
            }
            reach_[k] = pairs[k].second;
        }
        reachStart_.push_back(int(pairs.size()));
    }

    void cutPrimitive(int p, std::span<const int> candidates) {
        const auto& primitive = body_.primitives[size_t(p)];
        const Ball bound = ballAround(primitive.bounds());
        sideCount_ = 0; // sides kept from another primitive's splits are no use
        double covered = 0.0;
        std::vector<const PlacedCell*>& hit = hit_; // (scratch: a vector per primitive was an allocation or two)
        hit.clear();
        for (int c : candidates) {
            const Clip clip = clipToCell(p, bound, cells_[size_t(c)]);
            if (clip.kind == Clip::Nothing) continue;
            if (clip.kind == Clip::Whole) { // inside one cell: moved, not cut
                pieces_.push_back({p, c, -1});
                return;
            }
            addCutPiece(p, c, *clip.part);
            covered += shapes_.back().volume();
            hit.push_back(&cells_[size_t(c)]);
        }
        if (hit.empty()) {
            pieces_.push_back({p, far(), -1});
            return;
        }
        cutList_.push_back(p);
        if (covered >= primitive.volume() * (1.0 - 1e-12)) return;
        // What the free cells left: one convex part per outer cell it reaches (the pattern's
        // own cells, so neighbouring parts share their cut faces), and whatever lies beyond
        // the pattern by subtraction.
        std::vector<int>& outer = outer_;
        outer.clear();
        if (!outerCells_.empty()) outerTree_.query(primitive.bounds(), [&](int c) { outer.push_back(c); });
        std::sort(outer.begin(), outer.end());
        for (int c : outer) {
            const Clip clip = clipToCell(p, bound, outerCells_[size_t(c)]);
            if (clip.kind == Clip::Nothing) continue;
            addCutPiece(p, far(), *clip.part); // never whole: a free cell took a part
            covered += shapes_.back().volume();
            hit.push_back(&outerCells_[size_t(c)]);
        }
        if (covered >= primitive.volume() * (1.0 - 1e-12)) return;
        // The cells that cut it fill all of the pattern's domain within it when the domain is
        // convex: one region to subtract, of a few planes, instead of every cell.
        if (domain_.planes.empty()) cutRemainder(p, hit);
        else cutRemainder(p, {&domain_});
    }

    // The part of the primitive outside every cell that cut it, as convex parts:
    // R \ cell = ∪_k R ∩ {below planes 1..k-1} ∩ {above plane k}.
    // A part wholly beyond one face of the cell (no cut needed to know) stays as it is.
    [[gnu::noinline]] void cutRemainder(int p, const std::vector<const PlacedCell*>& hit) {
        // The parts live in remainderParts_, kept from primitive to primitive so that their
        // buffers are reused (a vector of solids per primitive, the original copied and every
        // part moved out, cost ~2 M instructions of allocation and copies in five events); rest
        // and next list them by index. A deque: a part's address stays while more are added.
        std::vector<int>& rest = restParts_;
        std::vector<int>& next = nextParts_;
        if (remainderParts_.empty()) remainderParts_.emplace_back();
        remainderParts_[0] = original(p);
        rest.assign(1, 0);
        int used = 1; // parts in use: [0, used)
        for (const PlacedCell* cell : hit) {
            next.clear();
            for (const int r : rest) {
                if (beyondAFace(remainderParts_[size_t(r)], *cell)) {
                    next.push_back(r);
                    continue;
                }
                const size_t first = next.size();
                const Solid* in = &remainderParts_[size_t(r)];
                bool meets = true;
                for (const auto& plane : cell->planes) {
                    Solid& below = in == &scratch_[0] ? scratch_[1] : scratch_[0];
                    if (used == int(remainderParts_.size())) remainderParts_.emplace_back();
                    Solid& above = remainderParts_[size_t(used)]; // taken only when split
                    const auto outcome =
                        splitter_.split(*in, plane.normal, plane.offset, settings_.snapTolerance, ids_, below, &above);
                    if (outcome == SolidSplitter::Outcome::Above) {
                        meets = false;
                        break;
                    }
                    if (outcome == SolidSplitter::Outcome::Split) {
                        next.push_back(used++);
                        in = &below;
                    }
                }
                if (!meets) {
                    next.resize(first);
                    next.push_back(r);
                }
            }
            std::swap(rest, next);
        }
        for (const int r : rest) addCutPiece(p, far(), remainderParts_[size_t(r)]);
    }

    // Some face of the cell has the solid above it and nothing of it below (as split() judges).
    bool beyondAFace(const Solid& solid, const PlacedCell& cell) const {
        const double tolerance = settings_.snapTolerance;
        for (const auto& plane : cell.planes) {
            bool above = false, below = false;
            for (const auto& v : solid.positions) {
                const double s = plane.normal.dot(v) - plane.offset;
                above |= s > tolerance;
                below |= s < -tolerance;
            }
            if (above && !below) return true;
        }
        return false;
    }

    // The pattern cut nothing free: every primitive stays where it was.
    bool untouched() const {
        return std::all_of(pieces_.begin(), pieces_.end(), [&](const Piece& p) { return p.region == far(); });
    }
    // The body as it is, one piece (its visual mesh unchanged: no inner faces shown).
    FractureResult wholeBody() const {
        FractureResult result;
        result.pieces.push_back(body_);
        result.sharedIds.emplace_back(size_t(body_.globalIdCount));
        std::iota(result.sharedIds.back().begin(), result.sharedIds.back().end(), 0);
        result.cells.push_back(-1);
        result.hullIsClear.push_back(false);
        result.parents.emplace_back(body_.primitives.size());
        std::iota(result.parents.back().begin(), result.parents.back().end(), 0);
        result.clipped.emplace_back(body_.primitives.size(), false);
        result.remainder = 0;
        return result;
    }

    void connect(int a, int b) {
        edges_.emplace_back(std::min(a, b), std::max(a, b));
        islands_.unite(a, b);
    }
    bool touching(int a, int b) const {
        const Piece& pa = pieces_[size_t(a)];
        const Piece& pb = pieces_[size_t(b)];
        if (pa.solid < 0 && pb.solid < 0) return true; // both whole: the body's own connection
        if (!shape(a).bounds().inflated(body_.contactTolerance).overlaps(shape(b).bounds())) return false;
        // A vertex id is one point of the rest shape (new ones within the snap tolerance), so
        // pieces that share one touch: most pairs here do (the same cut across two neighbours
        // makes the same crack vertices), and the id test costs a fraction of the distance query.
        // b's ids first: in the joining (a of the connection's first primitive) a shared id
        // is most often b's first, and then 6,251 four-id compares per event of the 16k shell
        // find it where a's ids first took 16,032.
        if (settings_.snapTolerance <= body_.contactTolerance &&
            geometry::shareAnId(shape(b).globalIds(), shape(a).globalIds()))
            return true;
        return geometry::withinTolerance(shape(a), shape(b), body_.contactTolerance);
    }
    // Connections recomputed only where something was cut: pieces of connected primitives
    // (or of one primitive) in the same region that still touch.
    // The body's own connections between two whole primitives of the far region only join
    // islands here: they are not listed in edges_ (tens of thousands for a large body whose
    // rest is edited in place); assemble() adds them for the far islands that become bodies.
    // (The far unions first, then the rest: islands are the same sets whatever the order of
    // unions, and edges_ comes from joinPiecesOfTouched in connection order as before.)
    [[gnu::noinline]] void findIslands() {
        uniteWholeFar();
        joinPiecesOfTouched();
        // Only a clipped primitive has several pieces: its list, not all ~16,000 primitives.
        for (int p : cutList_)
            for (int a = firstPiece_[size_t(p)]; a < firstPiece_[size_t(p) + 1]; ++a)
                for (int b = a + 1; b < firstPiece_[size_t(p) + 1]; ++b)
                    if (pieces_[size_t(a)].region == pieces_[size_t(b)].region && touching(a, b)) connect(a, b);
    }

    // Makes islands_ with the pieces of the body's connections between two whole far
    // primitives united (~60k of the 16k shell's ~63k), lists the others in
    // touchedConnections_ (ascending) and sets connectionsSorted_. One loop with no call in
    // it, so that its arrays stay in registers, on a union-find over the primitives whose
    // array also marks those not whole far (-1): a connection into the island of the one
    // before is told by one load. (With the joining called from inside the loop, and a look-up
    // of each end's piece, it took ~20 instructions a connection; ~10 now.)
    [[gnu::noinline]] void uniteWholeFar() {
        const size_t count = body_.connections.size();
        // Room for every connection, written only where listed (not zeroed first).
        const std::unique_ptr<int[]> touched(new int[count]);
        const std::unique_ptr<int[]> up = wholeFarForest();
        const FarUnions done = uniteAlong(body_.connections.data(), count, up.get(), touched.get());
        islands_ = piecesForest(up.get());
        touchedConnections_.assign(touched.get(), touched.get() + done.listed);
        connectionsSorted_ = done.sorted;
    }

    // Per primitive: itself (a root) when whole far, else -1.
    std::unique_ptr<int[]> wholeFarForest() const {
        const size_t primitives = body_.primitives.size();
        std::unique_ptr<int[]> up(new int[primitives]);
        for (size_t p = 0; p < primitives; ++p) up[p] = wholeFar_[p] < 0 ? -1 : int(p);
        return up;
    }

    // The pieces' union-find from one over the primitives (`up`, -1 for those not whole far):
    // a whole far primitive's piece under its parent's piece (pieces are numbered in primitive
    // order, so the parent's comes first, as UnionFind asks), every other piece alone.
    geometry::UnionFind piecesForest(const int* up) const {
        std::vector<int> parent(pieces_.size());
        std::iota(parent.begin(), parent.end(), 0);
        const int* const wholeFar = wholeFar_.data();
        for (int p = 0, count = int(body_.primitives.size()); p < count; ++p)
            if (up[p] >= 0) parent[size_t(wholeFar[p])] = wholeFar[up[p]];
        return geometry::UnionFind(std::move(parent));
    }

    // For each body connection with an end that is not whole in the far region
    // (touchedConnections_), its ends' pieces of one region that still touch are connected.
    // One loop, through plain pointers: with a call per connection (~4.4k an event of the 16k
    // shell) its entry, exit and reloads were ~1 M instructions of five events.
    [[gnu::noinline]] void joinPiecesOfTouched() {
        // ~1.2 edges a connection there (measured; a connection between two cut primitives can
        // make more): room for two each, so that edges_ rarely grows.
        edges_.reserve(edges_.size() + 2 * touchedConnections_.size());
        const std::pair<int, int>* const connections = body_.connections.data();
        const int* const firstPiece = firstPiece_.data();
        const Piece* const piece = pieces_.data();
        for (const int c : touchedConnections_) {
            const auto [a, b] = connections[c];
            // The ranges in locals: connect() writes memory that could alias them.
            const int aEnd = firstPiece[a + 1], bBegin = firstPiece[b], bEnd = firstPiece[b + 1];
            for (int pa = firstPiece[a]; pa < aEnd; ++pa) {
                const int region = piece[pa].region;
                for (int pb = bBegin; pb < bEnd; ++pb)
                    if (piece[pb].region == region && touching(pa, pb)) connect(pa, pb);
            }
        }
    }

    // The piece of primitive p when p stays whole in the far region, else -1.
    int wholeFar(int p) const { return wholeFar_[size_t(p)]; }

    // Components in order of their smallest piece (the union-find root), each in piece order.
    // Each list is sized before it is filled: one large body's rest holds ~16,000 pieces, and
    // growing it push by push cost about 1 M instructions per call (callgrind).
    std::vector<std::vector<int>> groups() const {
        const int n = int(pieces_.size());
        // Per piece its group, then per group its size (room for n groups): written before
        // read, so not zeroed. Through plain pointers: with vectors their ends were reloaded
        // at each piece (~27 instructions a piece in all, ~0.55 M a call on the 16k shell).
        const std::unique_ptr<int[]> scratch(new int[2 * size_t(n)]);
        int* const groupOf = scratch.get();
        int* const sizes = groupOf + n;
        int count = 0;
        // A piece's parent comes before it (UnionFind::parent) and is in its group: one load
        // a piece, no find. A group is numbered at its root, its smallest piece.
        for (int i = 0; i < n; ++i) {
            const int up = islands_.parent(i);
            if (up == i) {
                groupOf[i] = count;
                sizes[count++] = 1;
                continue;
            }
            const int g = groupOf[up];
            groupOf[i] = g;
            ++sizes[g];
        }
        std::vector<std::vector<int>> out(static_cast<size_t>(count));
        std::vector<int*> fill(static_cast<size_t>(count)); // where each group's next piece goes
        for (int g = 0; g < count; ++g) {
            out[size_t(g)].resize(size_t(sizes[g]));
            fill[size_t(g)] = out[size_t(g)].data();
        }
        int** const next = fill.data();
        for (int i = 0; i < n; ++i) *next[groupOf[i]]++ = i;
        return out;
    }

    // Primitive adjacency in one flat list (neighbours[start[p] .. start[p + 1])), each
    // primitive's neighbours in the order of the body's connections, over the connections
    // findIslands listed only (an end not whole in the far region): two whole far primitives
    // are in one island already, so a connection between them gives a small island no
    // contact. The same neighbours in the same order, less those: over all ~63k connections of
    // the 16k shell the list cost ~2 M instructions, most of the event's merging.
    void touchedAdjacency(std::vector<int>& start, std::vector<int>& neighbours) const {
        start.assign(body_.primitives.size() + 1, 0);
        for (const int c : touchedConnections_) {
            const auto [a, b] = body_.connections[size_t(c)];
            ++start[size_t(a) + 1];
            ++start[size_t(b) + 1];
        }
        for (size_t p = 1; p < start.size(); ++p) start[p] += start[p - 1];
        neighbours.resize(size_t(start.back()));
        std::vector<int> fill(start.begin(), start.end() - 1);
        for (const int c : touchedConnections_) {
            const auto [a, b] = body_.connections[size_t(c)];
            neighbours[size_t(fill[size_t(a)]++)] = b;
            neighbours[size_t(fill[size_t(b)]++)] = a;
        }
    }

    // A fragment below the minimum size joins the largest fragment one of its pieces touches.
    // Returns the islands after that, as groups() lists them (built from the merge chains when
    // some island merged).
    [[gnu::noinline]] std::vector<std::vector<int>> mergeSmallIslands() {
        const double smallest = std::pow(settings_.minimumPieceSize, 3);
        SmallMerge merge;
        merge.islands = groups();
        for (size_t index = 0; index < merge.islands.size(); ++index) {
            if (!smallIsland(merge.islands[index], smallest)) continue;
            if (merge.nextHeld.empty()) startMerge(merge); // only when some fragment is small
            const int root = islands_.find(merge.islands[index].front());
            const int own = merge.islandAt(root);
            std::vector<Contact> contacts;
            const int best = largestTouched(merge, own, root, contacts);
            if (best < 0) continue; // touches nothing: it was a separate part of the body already
            join(merge, own, best, contacts);
        }
        merged_ = merge.merged;
        if (merge.merged) return mergedIslands(merge);
        return std::move(merge.islands);
    }
    // mergeSmallIslands' state; all but the islands built at the first small one (startMerge).
    struct SmallMerge {
        std::vector<std::vector<int>> islands; // groups() before any merge
        // Primitive adjacency in one flat list (start[p] .. start[p + 1]), each primitive's
        // neighbours in the order of the body's connections.
        std::vector<int> start, neighbours;
        // Per island root: its volume (summed in piece order) once summed whole (fresh), until
        // a merge grows it.
        std::vector<double> islandVolume;
        std::vector<char> fresh;
        // Per island that is its root's own (its front, its smallest piece, is the root: a
        // union keeps the smaller root), the islands merged into it so far, itself first, as a
        // chain: nextHeld links them, lastHeld is the chain's end. An island merged as small
        // after others were merged into it (A into B, then B into E) joins by the contacts of
        // all of them, not only its own: A's with E are connected too.
        std::vector<int> nextHeld, lastHeld;
        bool merged = false;
        int islandAt(int root) const { // the island whose front is this root
            return int(std::lower_bound(islands.begin(), islands.end(), root,
                                        [](const std::vector<int>& island, int r) { return island.front() < r; }) -
                       islands.begin());
        }
    };
    struct Contact {
        int piece, other, island; // a piece of this island, one it touches, that one's island root
    };
    // The pieces of a chain (an island and those merged into it, from `head`) in piece order:
    // a walk over the chain's lists, each in piece order, taking the smallest next piece.
    class ChainPieces {
    public:
        ChainPieces(const SmallMerge& m, int head) {
            for (int h = head; h >= 0; h = m.nextHeld[size_t(h)]) {
                const std::vector<int>& island = m.islands[size_t(h)];
                lists_.emplace_back(island.data(), island.data() + island.size());
                count_ += island.size();
            }
        }
        // Every piece, in the order next() gives them: merged list by list (std::merge is
        // ~0.4 M instructions cheaper than next() over the 16k shell's rest of ~16.6k pieces).
        std::vector<int> all() const {
            if (lists_.size() == 1) return {lists_[0].first, lists_[0].second};
            std::vector<int> out(count_), both(lists_.size() > 2 ? count_ : 0);
            auto merged = std::merge(lists_[0].first, lists_[0].second, lists_[1].first, lists_[1].second, out.begin());
            for (size_t k = 2; k < lists_.size(); ++k) {
                merged = std::merge(out.begin(), merged, lists_[k].first, lists_[k].second, both.begin());
                out.swap(both); // `merged` still ends what was merged, now in `out`
            }
            return out;
        }
        // The next piece, or -1 once every one was given.
        int next() {
            auto smallest = lists_.end();
            for (auto l = lists_.begin(); l != lists_.end(); ++l)
                if (l->first != l->second && (smallest == lists_.end() || *l->first < *smallest->first)) smallest = l;
            return smallest == lists_.end() ? -1 : *smallest->first++;
        }

    private:
        std::vector<std::pair<const int*, const int*>> lists_;
        size_t count_ = 0; // pieces in all
    };
    // The islands after the merges, as groups() lists them (in order of their smallest piece,
    // each in piece order) from the chains: each island that was not merged into another, with
    // those merged into it merged in by piece order (its front, the smallest, is the root). A
    // merge of the rest's ~16.6k pieces with a small island's instead of a groups() over every
    // piece (~0.39 M instructions a call on the 16k shell).
    static std::vector<std::vector<int>> mergedIslands(SmallMerge& m) {
        std::vector<char> held(m.islands.size(), 0); // merged into another
        for (const int next : m.nextHeld)
            if (next >= 0) held[size_t(next)] = 1;
        std::vector<std::vector<int>> out;
        for (size_t h = 0; h < m.islands.size(); ++h) {
            if (held[h]) continue;
            if (m.nextHeld[h] < 0) { // nothing merged into it
                out.push_back(std::move(m.islands[h]));
                continue;
            }
            out.push_back(ChainPieces(m, int(h)).all());
        }
        return out;
    }
    // Summed only until it reaches the minimum (a sum of volumes only grows, also in floating
    // point), so the rest's ~16,000 pieces are not all read: the same decision.
    bool smallIsland(const std::vector<int>& members, double smallest) const {
        double v = 0.0;
        for (size_t k = 0; k < members.size() && v < smallest; ++k) v += volume(members[k]);
        return v < smallest;
    }
    // Primitive adjacency; no island volume yet (islandVolume sums them when asked: summing
    // all here read the volume of each of the rest's ~16.6k pieces, one cache line each, ~2/3
    // of mergeSmallIslands' own time samples).
    void startMerge(SmallMerge& m) {
        touchedAdjacency(m.start, m.neighbours);
        m.islandVolume.assign(pieces_.size(), 0.0);
        m.fresh.assign(pieces_.size(), 0);
        m.nextHeld.assign(m.islands.size(), -1);
        m.lastHeld.resize(m.islands.size());
        std::iota(m.lastHeld.begin(), m.lastHeld.end(), 0);
    }
    // The volume of the island of this root: the pieces of the islands merged into it (its
    // chain) in piece order, as a sum over all pieces gave it, but only until the sum exceeds
    // `bound` (then that part: the whole only passes it, a sum of volumes only grows). Kept
    // when summed whole.
    double islandVolume(SmallMerge& m, int root, double bound) {
        if (m.fresh[size_t(root)]) return m.islandVolume[size_t(root)];
        ChainPieces chain(m, m.islandAt(root));
        double w = 0.0;
        while (w <= bound) {
            const int piece = chain.next();
            if (piece < 0) { // summed whole
                m.islandVolume[size_t(root)] = w;
                m.fresh[size_t(root)] = 1;
                return w;
            }
            w += volume(piece);
        }
        return w;
    }
    // The island of most volume of these distinct roots (the smallest root on a tie), or -1.
    // The one of most pieces (the rest, ~16.6k, when a small island touches it) is summed last
    // and only until it exceeds every other: then it is the largest, whatever the others are.
    // Alone, it is summed not at all.
    int largestOf(SmallMerge& m, const std::vector<int>& roots) {
        if (roots.size() < 2) return roots.empty() ? -1 : roots.front();
        auto pieces = [&](int root) {
            size_t n = 0;
            for (int h = m.islandAt(root); h >= 0; h = m.nextHeld[size_t(h)]) n += m.islands[size_t(h)].size();
            return n;
        };
        const int most = *std::max_element(roots.begin(), roots.end(), [&](int a, int b) { return pieces(a) < pieces(b); });
        int best = -1;
        double bestVolume = -1.0;
        auto consider = [&](int root, double w) {
            if (w > bestVolume || (w == bestVolume && root < best)) {
                bestVolume = w;
                best = root;
            }
        };
        for (int root : roots)
            if (root != most) consider(root, islandVolume(m, root, std::numeric_limits<double>::infinity()));
        consider(most, islandVolume(m, most, bestVolume));
        return best;
    }
    // The root of the largest island that the island `own` (root `root`) and those merged
    // into it touch (the smallest root on a tie), or -1; every contact found into `contacts`.
    int largestTouched(SmallMerge& m, int own, int root, std::vector<Contact>& contacts) {
        auto consider = [&](int piece, int q) {
            if (islands_.find(q) == root || !touching(piece, q)) return;
            contacts.push_back({piece, q, islands_.find(q)});
        };
        for (int h = own; h >= 0; h = m.nextHeld[size_t(h)])
            for (int piece : m.islands[size_t(h)]) {
                const int parent = pieces_[size_t(piece)].parent;
                for (int q = firstPiece_[size_t(parent)]; q < firstPiece_[size_t(parent) + 1]; ++q) consider(piece, q);
                for (int k = m.start[size_t(parent)]; k < m.start[size_t(parent) + 1]; ++k) {
                    const int n = m.neighbours[size_t(k)];
                    for (int q = firstPiece_[size_t(n)]; q < firstPiece_[size_t(n) + 1]; ++q) consider(piece, q);
                }
            }
        std::vector<int> touched(contacts.size());
        std::transform(contacts.begin(), contacts.end(), touched.begin(), [](const Contact& c) { return c.island; });
        std::sort(touched.begin(), touched.end());
        touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
        return largestOf(m, touched);
    }
    // Joins the island `own` to the one of root `best` by its contacts with it.
    void join(SmallMerge& m, int own, int best, const std::vector<Contact>& contacts) {
        // By the roots found before any union: the first connect may make this island's
        // root the joined one's, after which a find no longer gives `best`.
        for (const Contact& c : contacts)
            if (c.island == best) connect(c.piece, c.other);
        // The joined island's root is the smaller of the two: its chain takes the other's.
        const int joined = islands_.find(best);
        const int into = m.islandAt(joined), other = into == own ? m.islandAt(best) : own;
        m.nextHeld[size_t(m.lastHeld[size_t(into)])] = other;
        m.lastHeld[size_t(into)] = m.lastHeld[size_t(other)];
        m.fresh[size_t(joined)] = 0; // merged: its volume grew
        m.merged = true;
    }

    // `fragments`: the islands (groups()).
    [[gnu::noinline]] FractureResult assemble(std::vector<std::vector<int>> fragments) {
        // Fragments of cells in pattern order, then the islands of the rest; each in piece order.
        std::vector<int> regions = regionsOf(fragments);
        sortByRegion(fragments, regions);
        auto regionOf = [&](size_t f) { return regions[f]; };
        // Filled with the fragment of most pieces (a large body's rest, ~16,000), the others written.
        size_t most = 0;
        for (size_t f = 1; f < fragments.size(); ++f)
            if (fragments[f].size() > fragments[most].size()) most = f;
        std::vector<int> fragmentOf(pieces_.size(), int(most));
        for (size_t f = 0; f < fragments.size(); ++f)
            if (f != most)
                for (int m : fragments[f]) fragmentOf[size_t(m)] = int(f);
        const int remainder = largestFarIsland(fragments, regions);

        FractureResult result;
        result.primitivesCut = int(cutList_.size());
        FragmentSurface& surface = *surface_;
        const bool inPlace = settings_.remainderInPlace && remainder >= 0 && !surface.closed();
        std::vector<std::vector<std::pair<int, int>>> fragmentEdges = edgesByFragment(fragmentOf, fragments.size());
        // The body's connections between whole far primitives (see findIslands), for every
        // fragment built as a new mesh that holds some (a far body, or a cell's fragment a far
        // island was merged into); an edited rest keeps its own.
        const std::vector<int> lostFarConnections =
            addFarConnections(fragments, inPlace ? remainder : -1, fragmentOf, fragmentEdges);
        const std::vector<bool> clear = hullsClear(fragments);
        geometry::MassProperties others; // every fragment but the rest
        for (size_t f = 0; f < fragments.size(); ++f) {
            if (inPlace && int(f) == remainder) continue;
            const int region = regionOf(f);
            result.cells.push_back(region == far() ? -1 : cells_[size_t(region)].cell);
            result.hullIsClear.push_back(clear[f]);
            auto [mesh, shared] = buildFragment(fragments[f], fragmentEdges[f], surface);
            result.parents.emplace_back();
            result.clipped.emplace_back();
            for (int m : fragments[f]) {
                result.parents.back().push_back(pieces_[size_t(m)].parent);
                result.clipped.back().push_back(pieces_[size_t(m)].solid >= 0);
            }
            if (int(f) == remainder) result.remainder = int(result.pieces.size());
            others += mesh.mass;
            result.pieces.push_back(std::move(mesh));
            result.sharedIds.push_back(std::move(shared));
        }
        if (inPlace) {
            result.remainderEdit = remainderEdit(fragments, remainder, fragmentOf, fragmentEdges[size_t(remainder)],
                                                 surface, withoutPart(body_.mass, others));
            // Every connection with an end the rest loses: a primitive the rest loses is not
            // whole in the far region (findIslands' list) or is whole there in another
            // fragment (the list above). The two lists are disjoint.
            auto& touched = result.remainderEdit->touchedConnections;
            touched.resize(touchedConnections_.size() + lostFarConnections.size());
            std::merge(touchedConnections_.begin(), touchedConnections_.end(), lostFarConnections.begin(),
                       lostFarConnections.end(), touched.begin());
        }
        return result;
    }

    // Adds to fragmentEdges the body's connections between two whole far primitives of every
    // fragment but `edited` (the rest edited in place, or -1), and returns their indices,
    // ascending: with findIslands' list, every connection the edited rest must look up.
    std::vector<int> addFarConnections(const std::vector<std::vector<int>>& fragments, int edited,
                                       const std::vector<int>& fragmentOf,
                                       std::vector<std::vector<std::pair<int, int>>>& fragmentEdges) const {
        // The primitives whole in the far region whose piece is in a fragment other than the
        // edited rest, flagged: a far body's, or a small far island's merged into a cell's
        // fragment (mergeSmallIslands), whatever region that fragment is of. Two connected
        // whole far primitives are in one island, so both or neither are flagged.
        std::vector<char> inFarBody(body_.primitives.size(), 0);
        std::vector<int> flagged;
        for (size_t f = 0; f < fragments.size(); ++f) {
            if (int(f) == edited) continue;
            for (int m : fragments[f])
                if (const int p = pieces_[size_t(m)].parent; wholeFar(p) == m) {
                    inFarBody[size_t(p)] = 1;
                    flagged.push_back(p);
                }
        }
        // Their connections (those whose first end is flagged), only when some is: found by
        // their first end when the connections are sorted by it (as findIslands found them),
        // else one load each of the ~63k of a 16k-primitive rest. The same connections as
        // testing both ends and the fragment of each, in the same order.
        std::vector<int> lost;
        if (flagged.empty()) return lost;
        std::sort(flagged.begin(), flagged.end());
        for (const int c : connectionsSorted_ ? connectionsStartingAt(body_.connections, flagged)
                                              : connectionsFrom(body_.connections, inFarBody)) {
            const auto [a, b] = body_.connections[size_t(c)];
            const int pa = wholeFar(a), pb = wholeFar(b);
            if (pb < 0) continue; // findIslands listed it
            lost.push_back(c);
            fragmentEdges[size_t(fragmentOf[size_t(pa)])].emplace_back(std::min(pa, pb), std::max(pa, pb));
        }
        return lost;
    }

    // edges_ by the fragment of their first end, in their order. Each list sized first: grown
    // edge by edge, the rest's was copied again at each doubling (~0.3 M instructions in five
    // events of the 16k shell).
    std::vector<std::vector<std::pair<int, int>>> edgesByFragment(const std::vector<int>& fragmentOf,
                                                                  size_t fragments) const {
        std::vector<int> count(fragments, 0);
        for (const auto& e : edges_) ++count[size_t(fragmentOf[size_t(e.first)])];
        std::vector<std::vector<std::pair<int, int>>> out(fragments);
        for (size_t f = 0; f < fragments; ++f) out[f].reserve(size_t(count[f]));
        for (const auto& e : edges_) out[size_t(fragmentOf[size_t(e.first)])].push_back(e);
        return out;
    }

    // Per fragment, its region: that of its pieces, or, for an island that small islands of
    // other regions were merged into (mergeSmallIslands), the region holding most of its volume
    // (the first piece's on a tie). A small cell fragment merged into the large far part beyond
    // it leaves that part far, so the part of the body holding most of the rest stays the rest;
    // a region by its first piece made it "cell 0's fragment", and a few end quads the rest.
    // By volume, not by whether it holds whole far primitives: a small far island of one whole
    // primitive merged into a cell's fragment leaves that fragment a cell's.
    std::vector<int> regionsOf(const std::vector<std::vector<int>>& fragments) const {
        std::vector<int> regions(fragments.size());
        for (size_t f = 0; f < fragments.size(); ++f) {
            const int first = pieces_[size_t(fragments[f].front())].region;
            regions[f] = merged_ ? regionOfMost(fragments[f], first) : first;
        }
        return regions;
    }
    // The region holding most of the volume of these pieces (`first` on a tie, and when they
    // are all of it: then no volume is summed).
    int regionOfMost(const std::vector<int>& members, int first) const {
        if (std::all_of(members.begin(), members.end(), [&](int m) { return pieces_[size_t(m)].region == first; }))
            return first;
        std::vector<std::pair<int, double>> volumes; // (region, volume), in order of first piece
        for (int m : members) {
            const int r = pieces_[size_t(m)].region;
            auto at = std::find_if(volumes.begin(), volumes.end(), [&](const auto& v) { return v.first == r; });
            if (at == volumes.end()) at = volumes.emplace(volumes.end(), r, 0.0);
            at->second += volume(m);
        }
        auto most = volumes.begin();
        for (auto v = volumes.begin(); v != volumes.end(); ++v)
            if (v->second > most->second) most = v;
        return most->first;
    }
    // Fragments by region, then by first piece (each keeps its region).
    static void sortByRegion(std::vector<std::vector<int>>& fragments, std::vector<int>& regions) {
        std::vector<size_t> order(fragments.size());
        std::iota(order.begin(), order.end(), size_t(0));
        std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) {
            return regions[a] != regions[b] ? regions[a] < regions[b] : fragments[a].front() < fragments[b].front();
        });
        std::vector<std::vector<int>> sorted(fragments.size());
        std::vector<int> sortedRegions(fragments.size());
        for (size_t k = 0; k < order.size(); ++k) {
            sorted[k] = std::move(fragments[order[k]]);
            sortedRegions[k] = regions[order[k]];
        }
        fragments = std::move(sorted);
        regions = std::move(sortedRegions);
    }

    // The indices of the connections whose first end is one of `firsts` (ascending), ascending,
    // for connections sorted by their first end: a binary search for each.
    static std::vector<int> connectionsStartingAt(const std::vector<std::pair<int, int>>& connections,
                                                  const std::vector<int>& firsts) {
        std::vector<int> out;
        auto at = connections.begin();
        for (const int p : firsts) {
            at = std::lower_bound(at, connections.end(), p, [](const auto& c, int first) { return c.first < first; });
            for (; at != connections.end() && at->first == p; ++at) out.push_back(int(at - connections.begin()));
        }
        return out;
    }

    // The indices of the connections whose first end is flagged, ascending. Its own function:
    // assemble's registers are taken, and the loop would keep its counters on the stack.
    [[gnu::noinline]] static std::vector<int> connectionsFrom(const std::vector<std::pair<int, int>>& connections,
                                                              const std::vector<char>& flagged) {
        std::vector<int> out;
        const std::pair<int, int>* connection = connections.data();
        const char* flag = flagged.data();
        for (int c = 0, count = int(connections.size()); c < count; ++c)
            if (flag[connection[c].first]) out.push_back(c);
        return out;
    }

    // The rest of the body: the largest island of the far region by volume (the first of equal
    // ones), or -1. The island of most pieces (a large body's rest, ~16,000 of them) is summed
    // last and only until it exceeds every other island: then it is the largest whatever its
    // other pieces add (a sum of volumes only grows), without reading every primitive it keeps.
    int largestFarIsland(const std::vector<std::vector<int>>& fragments, const std::vector<int>& regions) const {
        auto isFar = [&](size_t f) { return regions[f] == far(); };
        int most = -1;
        for (size_t f = 0; f < fragments.size(); ++f)
            if (isFar(f) && (most < 0 || fragments[f].size() > fragments[size_t(most)].size())) most = int(f);
        if (most < 0) return -1;
        std::vector<double> volumes(fragments.size(), 0.0);
        double others = -1.0;
        for (size_t f = 0; f < fragments.size(); ++f) {
            if (!isFar(f) || int(f) == most) continue;
            for (int m : fragments[f]) volumes[f] += volume(m);
            others = std::max(others, volumes[f]);
        }
        // Summed in a local (through the vector's element the pieces' arrays were reloaded at
        // each piece, ~40 instructions a piece): the same additions in the same order.
        const auto& rest = fragments[size_t(most)];
        double v = 0.0;
        for (size_t k = 0; k < rest.size() && v <= others; ++k) v += volume(rest[k]);
        volumes[size_t(most)] = v;
        if (v > others) return most;
        // Not ahead (v is its whole volume now): the first of the largest, as they come.
        int largest = -1;
        for (size_t f = 0; f < fragments.size(); ++f)
            if (isFar(f) && (largest < 0 || volumes[f] > volumes[size_t(largest)])) largest = int(f);
        return largest;
    }

    // Per fragment: FractureResult::hullIsClear. A cell usually holds one fragment; two when it
    // reaches both walls of a hollow body, or when a small island across the cut was merged
    // into its neighbour (mergeSmallIslands).
    std::vector<bool> hullsClear(const std::vector<std::vector<int>>& fragments) const {
        // Per placed cell, its pieces by fragment (sorted, so in any order of finding).
        std::vector<std::vector<std::pair<int, int>>> inCell(cells_.size()); // (fragment, piece)
        // Read from the fragments, not from every piece (~16.6k): an island unmerged is of one
        // region (connect() joins pieces of one region), so a far one holds no cell's pieces.
        const int farRegion = far();
        const Piece* piece = pieces_.data();
        for (size_t f = 0; f < fragments.size(); ++f) {
            if (!merged_ && piece[fragments[f].front()].region == farRegion) continue;
            for (const int m : fragments[f])
                if (const int r = piece[m].region; r != farRegion) inCell[size_t(r)].emplace_back(int(f), m);
        }
        for (auto& list : inCell) std::sort(list.begin(), list.end());
        // The vertices of a fragment's pieces in cell r.
        auto pointsIn = [&](int r, int f) {
            std::vector<Eigen::Vector3d> points;
            for (const auto& [g, m] : inCell[size_t(r)])
                if (g == f)
                    for (const auto& v : shape(m).vertices()) points.push_back(v);
            return points;
        };
        auto centroid = [](const std::vector<Eigen::Vector3d>& points) {
            Eigen::Vector3d c = Eigen::Vector3d::Zero();
            for (const auto& p : points) c += p;
            return Eigen::Vector3d(c / double(points.size()));
        };
        std::vector<bool> clear(fragments.size(), false);
        for (size_t f = 0; f < fragments.size(); ++f) {
            const int r = pieces_[size_t(fragments[f].front())].region;
            if (r == far() || std::any_of(fragments[f].begin(), fragments[f].end(),
                                          [&](int m) { return pieces_[size_t(m)].region != r; }))
                continue;
            const auto& list = inCell[size_t(r)];
            if (list.front().first == int(f) && list.back().first == int(f)) { // alone in its cell
                clear[f] = true;
                continue;
            }
            const std::vector<Eigen::Vector3d> own = pointsIn(r, int(f));
            const Eigen::Vector3d ownCentre = centroid(own);
            bool apart = true;
            for (size_t k = 0; k < list.size() && apart; ++k) {
                const int g = list[k].first;
                if (g == int(f) || (k > 0 && list[k - 1].first == g)) continue;
                const std::vector<Eigen::Vector3d> other = pointsIn(r, g);
                const Eigen::Vector3d axis = centroid(other) - ownCentre;
                double reach = -INFINITY, start = INFINITY;
                for (const auto& p : own) reach = std::max(reach, axis.dot(p));
                for (const auto& p : other) start = std::min(start, axis.dot(p));
                // Touching (within the snap tolerance) is allowed, as between neighbouring cells.
                apart = axis.norm() > 0.0 && reach <= start + settings_.snapTolerance * axis.norm();
            }
            clear[f] = apart;
        }
        return clear;
    }

    // The rest of the body as an edit of it (see RemainderEdit): only the primitives it loses,
    // the cut pieces it gains and the faces around them are looked at, beyond a few flat
    // passes over indices.
    // `rest`: the fragment kept as the body (fragments[rest]); fragmentOf: each piece's fragment.
    RemainderEdit remainderEdit(const std::vector<std::vector<int>>& fragments, int rest,
                                const std::vector<int>& fragmentOf, const std::vector<std::pair<int, int>>& edges,
                                FragmentSurface& surface, const geometry::MassProperties& mass) {
        RemainderEdit edit;
        edit.mass = mass;
        // The rest's cut pieces, in piece order.
        std::vector<int> cut;
        for (int m : cutPieces_)
            if (fragmentOf[size_t(m)] == rest) cut.push_back(m);
        const std::vector<char> lost = lostPrimitives(fragments, rest, fragmentOf, cut, edit.removed);
        int removedWithSource = 0;
        const std::vector<char> dropped = dropFacesOf(edit, surface, removedWithSource);
        std::vector<FragmentPart> parts = keptLosingTheirSource(edit, lost, dropped, surface, removedWithSource);
        for (int m : cut) parts.push_back({pieces_[size_t(m)].parent, cutFaces_[pieces_[size_t(m)].solid]});
        FragmentFaces faces = surface.build(parts);
        const FinalIds ids = swapShownIds(edit, faces);
        addCutPieces(edit, cut, ids);
        connectCutPieces(edit, cut, edges);
        return edit;
    }

    // Marks the primitives the rest loses and lists them, ascending, in `removed`. A primitive
    // is kept when it has a whole piece in the rest, lost otherwise: then it has a piece in
    // another fragment or a cut piece in the rest. Found from those (~1k pieces), not from the
    // rest's ~16k. (Marked, then listed in one ascending pass over the marks: sorting the ~6k
    // parents, with repeats, was ~0.3 M instructions a break, the pass ~0.05 M.)
    std::vector<char> lostPrimitives(const std::vector<std::vector<int>>& fragments, int rest,
                                     const std::vector<int>& fragmentOf, const std::vector<int>& cut,
                                     std::vector<int>& removed) const {
        std::vector<char> lost(body_.primitives.size(), 0);
        for (size_t f = 0; f < fragments.size(); ++f)
            if (int(f) != rest)
                for (int m : fragments[f]) lost[size_t(pieces_[size_t(m)].parent)] = 1;
        for (int m : cut) lost[size_t(pieces_[size_t(m)].parent)] = 1;
        auto wholeInRest = [&](int p) {
            for (int m = firstPiece_[size_t(p)]; m < firstPiece_[size_t(p) + 1]; ++m)
                if (pieces_[size_t(m)].solid < 0 && fragmentOf[size_t(m)] == rest) return true;
            return false;
        };
        forEachMarked(lost, [&](int p) {
            if (wholeInRest(p)) lost[size_t(p)] = 0;
            else removed.push_back(p);
        });
        return lost;
    }

    // Drops (edit.droppedFaces, ascending; marked in the result) the faces the removed
    // primitives showed: their source faces and every face the body lists as one of their own
    // (a piece of an earlier break, an inner face). A face left behind would show ids no
    // primitive carries any more, which nothing moves. Counts the removed primitives that have
    // a source face in `withSource`.
    std::vector<char> dropFacesOf(RemainderEdit& edit, const FragmentSurface& surface, int& withSource) const {
        std::vector<char> dropped(body_.visual.faces.size(), 0);
        auto drop = [&](int f) {
            if (!dropped[size_t(f)]) edit.droppedFaces.push_back(f);
            dropped[size_t(f)] = 1;
        };
        const int visualCount = int(body_.visual.positions.size());
        std::vector<int> buffer; // only grows: resized per face, it was a call a face
        const std::vector<int>& removed = edit.removed;
        for (size_t i = 0; i < removed.size(); ++i) {
            prefetchShapesAhead(i, removed.size(), false,
                          [&](size_t k) -> const auto& { return body_.primitives[size_t(removed[k])]; });
            const int p = removed[i];
            if (const int source = body_.sourceFace[size_t(p)]; source >= 0) {
                drop(source);
                ++withSource;
            }
            const auto& primitive = body_.primitives[size_t(p)];
            const int* const globalIds = primitive.globalIds().data();
            for (const auto& face : primitive.faces()) {
                // A body face has visual ids only: a face with an inner one is not looked up (a
                // shell prism's bottom and sides). Its ids are written out only once it is known
                // to be visual (~20 instructions less a face, ~31k faces in five events of the 16k
                // shell).
                if (!std::all_of(face.begin(), face.end(), [&](int v) { return globalIds[v] < visualCount; })) continue;
                if (buffer.size() < face.size()) buffer.resize(face.size());
                const std::span<int> ids(buffer.data(), face.size());
                for (size_t k = 0; k < face.size(); ++k) ids[k] = globalIds[face[k]];
                if (const int f = surface.shownFace(ids); f >= 0) drop(f);
            }
        }
        std::sort(edit.droppedFaces.begin(), edit.droppedFaces.end());
        return dropped;
    }

    // The parts of the kept primitives whose source face is dropped (edit.lostSourceFace):
    // they now show their own parts of it. Only looked for when there are some: the dropped
    // faces are the source of more primitives than the removed ones with a source face (each
    // is its own face's, dropped). (Through plain pointers: the vectors' members were
    // reloaded after every store, ~14 instructions a primitive.)
    std::vector<FragmentPart> keptLosingTheirSource(RemainderEdit& edit, const std::vector<char>& lost,
                                                    const std::vector<char>& dropped, const FragmentSurface& surface,
                                                    int removedWithSource) const {
        std::vector<FragmentPart> parts;
        int sourcesDropped = 0;
        for (int f : edit.droppedFaces) sourcesDropped += surface.primitivesOf(f);
        if (sourcesDropped <= removedWithSource) return parts;
        const int* sourceFace = body_.sourceFace.data();
        const char* isLost = lost.data();
        const char* isDropped = dropped.data();
        for (int p = 0, count = int(body_.primitives.size()); p < count; ++p) {
            const int source = sourceFace[p];
            if (source < 0 || isLost[p] || !isDropped[source]) continue;
            edit.lostSourceFace.push_back(p);
            parts.push_back({p, std::nullopt, /*sourceOnly=*/true});
        }
        return parts;
    }

    // Every fracture-wide id's id in the edited rest (see swapShownIds).
    struct FinalIds {
        int visualCount = 0; // the body's visual vertices: their ids never move
        int slotsEnd = 0;    // the new visual vertices are [visualCount, slotsEnd)
        // Per id from visualCount up. Not a std::vector: sized, it was zero-filled only for the
        // iota to overwrite (~0.4 M instructions in five events of the 16k shell).
        std::unique_ptr<int[]> inner;
        int operator()(int id) const { return id < visualCount ? id : inner[size_t(id - visualCount)]; }
    };

    // Ids the new faces show that were not visual vertices become the next visual ids: those
    // among the slots [V, V + k) stay, the others trade places with the slots' ids
    // (edit.idSwaps). The faces, in final ids, move into the edit.
    FinalIds swapShownIds(RemainderEdit& edit, FragmentFaces& faces) const {
        FinalIds to;
        const int visualCount = int(body_.visual.positions.size());
        const int idCount = ids_.firstId() + ids_.count();
        to.visualCount = visualCount;
        const size_t innerCount = static_cast<size_t>(idCount - visualCount);
        // Marked over the inner ids, then listed ascending (as a sort and unique of every
        // shown inner id did, ~6k a break, at several times the cost), into room for all (a
        // push_back was a call per id).
        std::vector<char> innerShown(innerCount, 0);
        for (const auto& face : faces.faces)
            for (int id : face)
                if (id >= visualCount) innerShown[size_t(id - visualCount)] = 1;
        std::unique_ptr<int[]> room(new int[innerCount]);
        size_t shownCount = 0;
        forEachMarked(innerShown, [&](int k) { room[shownCount++] = visualCount + k; });
        const std::span<const int> shown(room.get(), shownCount);
        to.slotsEnd = visualCount + int(shown.size());
        // Ids below visualCount never move (the slots start there, the ids swapped into them
        // lie past them), so the table covers only the inner ids: a shell's ids are nearly all
        // visual, and an iota over all of them was ~0.25 M instructions per break.
        to.inner.reset(new int[innerCount]);
        std::iota(to.inner.get(), to.inner.get() + innerCount, visualCount);
        std::vector<char> isShown(static_cast<size_t>(to.slotsEnd - visualCount), 0);
        std::vector<int> outside;
        for (int id : shown) {
            if (id < to.slotsEnd) isShown[size_t(id - visualCount)] = 1;
            else outside.push_back(id);
        }
        size_t next = 0;
        for (int slot = visualCount; slot < to.slotsEnd; ++slot) {
            if (isShown[size_t(slot - visualCount)]) continue;
            const int id = outside[next++];
            edit.idSwaps.emplace_back(slot, id);
            to.inner[size_t(slot - visualCount)] = id;
            to.inner[size_t(id - visualCount)] = slot;
        }
        for (auto& face : faces.faces)
            for (int& id : face) id = to(id);
        edit.faces = std::move(faces.faces);
        edit.crack = std::move(faces.crack);
        edit.newVisualPositions.resize(shown.size());
        edit.globalIdCount = idCount;
        return to;
    }

    // The rest's cut pieces in final ids (edit.added), and the positions of the new visual
    // vertices they carry.
    void addCutPieces(RemainderEdit& edit, const std::vector<int>& cut, const FinalIds& to) {
        edit.added.reserve(cut.size()); // grown by push_back it moved every piece again (fresh pages)
        for (size_t i = 0; i < cut.size(); ++i) {
            prefetchShapesAhead(i, cut.size(), true, [&](size_t k) -> const auto& { return shape(cut[k]); });
            const int m = cut[i];
            const auto& s = shape(m);
            const std::span<int> ids = mappedIds(s, to, [&](int id, size_t v) {
                if (id >= to.visualCount && id < to.slotsEnd) edit.newVisualPositions[size_t(id - to.visualCount)] = s.vertices()[v];
            });
            edit.added.push_back(takeShape(m, ids));
        }
    }

    // Connections of the cut pieces (those between kept primitives are the body's); a whole
    // piece's index is found from its primitive, only for these: a kept primitive's index
    // after the edit is its own less the lost ones before it.
    void connectCutPieces(RemainderEdit& edit, const std::vector<int>& cut,
                          const std::vector<std::pair<int, int>>& edges) const {
        const int kept = int(body_.primitives.size()) - int(edit.removed.size());
        const std::vector<int>& removed = edit.removed;
        // Per piece, its index if cut, else -1: buildFragment's map, -1 everywhere between uses
        // (a piece-sized vector filled with -1 here was a ~66 kB memset a break of the 16k shell).
        std::vector<int>& cutIndex = fragmentMaps().localPiece;
        makeRoom(cutIndex, pieces_.size());
        const int cutCount = int(cut.size());
        const Unset unset{cutIndex, cut.data(), cutCount};
        for (size_t k = 0; k < cut.size(); ++k) cutIndex[size_t(cut[k])] = kept + int(k);
        auto indexOf = [&](int m) {
            if (cutIndex[size_t(m)] >= 0) return cutIndex[size_t(m)];
            const int p = pieces_[size_t(m)].parent;
            return p - countBelow(removed, p);
        };
        for (const auto& [a, b] : edges) {
            if (cutIndex[size_t(a)] < 0 && cutIndex[size_t(b)] < 0) continue;
            const int ia = indexOf(a), ib = indexOf(b);
            if (ia != ib) edit.connections.emplace_back(std::min(ia, ib), std::max(ia, ib));
        }
    }

    std::pair<geometry::PhysicalMesh, std::vector<int>> buildFragment(const std::vector<int>& members,
                                                                      const std::vector<std::pair<int, int>>& edges,
                                                                      FragmentSurface& surface) {
        FragmentFaces faces = surface.build(partsOf(members));
        LocalIds local = startLocalIds();
        const Unset unset{local.localOf, local.order, local.used};
        geometry::PhysicalMesh mesh;
        takeVisualFaces(faces, local, mesh);
        addPrimitives(members, local, mesh);
        mesh.sourceFace = std::move(faces.sourceFace); // one per part, the members in order
        addConnections(members, edges, mesh);
        std::vector<int> shared(local.order, local.order + local.used);
        mesh.name = body_.name;
        mesh.globalIdCount = int(shared.size());
        mesh.thickness = body_.thickness;
        mesh.density = body_.density;
        mesh.contactTolerance = body_.contactTolerance;
        return {std::move(mesh), std::move(shared)};
    }
    std::vector<FragmentPart> partsOf(const std::vector<int>& members) const {
        std::vector<FragmentPart> parts;
        parts.reserve(members.size());
        for (int m : members) {
            const Piece& p = pieces_[size_t(m)];
            if (p.solid < 0) parts.push_back({p.parent, std::nullopt});
            else parts.push_back({p.parent, cutFaces_[p.solid]});
        }
        return parts;
    }
    // A fragment's local ids: the visual vertices first (PhysicalMesh keeps ids below
    // visual.positions.size() for them), then the inner ones. localOf is -1 everywhere between
    // fragments; order[0, used) lists what this one set. (Into room for every id, not by
    // push_back: an out-of-line call per id, ~0.8 M instructions in five events of the 16k
    // shell.)
    struct LocalIds {
        std::vector<int>& localOf;
        int* order;
        int used = 0;
        int operator()(int id) {
            int& local = localOf[size_t(id)];
            if (local < 0) {
                local = used;
                order[used++] = id;
            }
            return local;
        }
    };
    LocalIds startLocalIds() {
        const size_t idCount = size_t(ids_.firstId() + ids_.count());
        FragmentMaps& maps = fragmentMaps();
        makeRoom(maps.localOf, idCount);
        if (maps.idOrder.size() < idCount) maps.idOrder.resize(idCount);
        return {maps.localOf, maps.idOrder.data()};
    }
    // The faces in local ids (their ids are the fragment's visual ones, numbered first).
    static void takeVisualFaces(FragmentFaces& faces, LocalIds& local, geometry::PhysicalMesh& mesh) {
        for (auto& face : faces.faces)
            for (int& id : face) id = local(id);
        mesh.visual.faces = std::move(faces.faces);
        mesh.visual.crackFace = std::move(faces.crack);
        // The lists had room for every face the parts could show, up to ~6 times those shown
        // (~2 MB for a large far fragment of an open shell); the body keeps what it shows.
        if (mesh.visual.faces.capacity() > 2 * mesh.visual.faces.size()) {
            mesh.visual.faces.shrink_to_fit();
            mesh.visual.crackFace.shrink_to_fit();
        }
        mesh.visual.positions.resize(size_t(local.used));
    }
    // The members' shapes in local ids, the visual positions they carry, the mass.
    void addPrimitives(const std::vector<int>& members, LocalIds& local, geometry::PhysicalMesh& mesh) {
        const int visualCount = int(mesh.visual.positions.size());
        std::vector<char> placed(size_t(visualCount), 0);
        mesh.primitives.reserve(members.size()); // no polyhedron moved by a reallocation
        for (size_t i = 0; i < members.size(); ++i) {
            prefetchShapesAhead(i, members.size(), true, [&](size_t k) -> const auto& { return shape(members[k]); });
            const int m = members[i];
            const auto& s = shape(m);
            const std::span<int> ids = mappedIds(s, local, [&](int id, size_t v) {
                if (id >= visualCount || placed[size_t(id)]) return;
                placed[size_t(id)] = 1;
                mesh.visual.positions[size_t(id)] = s.vertices()[v];
            });
            mesh.mass += s.massProperties(body_.density);
            mesh.primitives.push_back(takeShape(m, ids));
        }
    }
    // Shape s's ids through `map`, written into pieceIds' storage (for takeShape), and
    // onVertex(id, v) for each of its vertices v.
    template <typename Map, typename OnVertex>
    std::span<int> mappedIds(const geometry::ConvexPolyhedron& s, Map&& map, const OnVertex& onVertex) {
        const std::vector<int>& from = s.globalIds();
        const std::span<int> ids = pieceIds(from.size());
        for (size_t v = 0; v < ids.size(); ++v) {
            ids[v] = map(from[v]);
            onVertex(ids[v], v);
        }
        return ids;
    }
    // Prefetching for the loops over shapes that stalled on them (dropFacesOf, addCutPieces,
    // addPrimitives): a body primitive or a cut piece is scattered over the heap and was last
    // read by the cutting, so its object, its ids, vertices, planes and face list were a cache
    // miss each. Two steps ahead the shape itself, one step ahead its ids and face list, and
    // with `withGeometry` its vertices and planes: the first line of each. shapeAt(k) is the
    // loop's k-th shape. asm16c (perf, 16k shell x 64 cells): remainderEdit 202 -> 142 and
    // buildFragment 402 -> 323 samples. Every line of each (prefetchRange) cost 1.3 M more
    // instructions in five events for no time gain (8 interleaved pairs). Hints alone, so
    // inlined by force (see Prefetch.h).
    static constexpr size_t kShapesAhead = 4;
    template <typename ShapeAt>
    [[gnu::always_inline]] static void prefetchShapesAhead(size_t i, size_t n, bool withGeometry, const ShapeAt& shapeAt) {
        if (i + 2 * kShapesAhead < n) __builtin_prefetch(&shapeAt(i + 2 * kShapesAhead));
        if (i + kShapesAhead >= n) return;
        const geometry::ConvexPolyhedron& s = shapeAt(i + kShapesAhead);
        __builtin_prefetch(s.globalIds().data());
        __builtin_prefetch(&s.faces());
        if (!withGeometry) return;
        __builtin_prefetch(s.vertices().data());
        __builtin_prefetch(s.planes().data());
    }
    // The connections between the members (edges: pairs of pieces), in member indices.
    void addConnections(const std::vector<int>& members, const std::vector<std::pair<int, int>>& edges,
                        geometry::PhysicalMesh& mesh) {
        std::vector<int>& localPiece = fragmentMaps().localPiece;
        makeRoom(localPiece, pieces_.size());
        const int memberCount = int(members.size());
        const Unset unset{localPiece, members.data(), memberCount};
        for (int i = 0; i < memberCount; ++i) localPiece[size_t(members[size_t(i)])] = i;
        // Room for every edge at once (grown by emplace_back it was ~8 allocations and
        // copies a fragment); a fragment keeps at most its pieces' pairs and their repeats.
        mesh.connections.reserve(edges.size());
        for (const auto& [a, b] : edges) {
            const int la = localPiece[size_t(a)], lb = localPiece[size_t(b)];
            if (la != lb) mesh.connections.emplace_back(std::min(la, lb), std::max(la, lb));
        }
        sortPairs(mesh.connections, int(members.size()), pairCount_, pairScratch_);
    }

    const geometry::PhysicalMesh& body_;
    const FracturePattern& pattern_;
    const Placement& where_;
    const CutSettings& settings_;
    const PrimitiveIndex index_; // a pointer and an isometry: a copy, so no temporary is held
    // See cellsReachingByTree: the primitives some free cell may reach (ascending), and per
    // such primitive (k) those cells, reach_[reachStart_[k] .. reachStart_[k + 1]).
    std::vector<int> reached_, reachStart_, reach_;
    std::vector<int> leaves_;             // scratch of cellsReachingByTree: a cell's tree leaves
    NewVertexIds ids_;
    SolidSplitter splitter_;
    std::vector<PlacedCell> cells_;      // within the radius
    std::vector<PlacedCell> outerCells_; // the others
    PlacedCell domain_;                  // the region all cells fill, when convex (planes only), else no planes
    BoxGrid grid_; // the free cells' boxes
    geometry::AabbTree outerTree_;
    Eigen::Matrix3d rotation_;
    std::vector<int> placedPlane_;        // pattern plane → index in planes_, or -1
    std::vector<geometry::Plane> planes_; // placed pattern planes, body coordinates
    geometry::Aabb cellBounds_;
    std::vector<Piece> pieces_;
    std::vector<int> firstPiece_; // per primitive: its first piece (+ total); a primitive's pieces are contiguous
    std::vector<int> wholeFar_;   // per primitive: see wholeFar() (a look-up per body connection)
    CutFaceStore cutFaces_; // per cut piece (Piece::solid), its faces
    std::vector<geometry::ConvexPolyhedron> shapes_; // per solid
    Solid original_;      // the solid of primitive originalOf_ (see original())
    std::vector<int> faceIds_; // scratch: a face's ids
    std::optional<FragmentSurface> surface_; // the body's surface (fractureMesh, not cutMesh)
    int originalOf_ = -1;
    Solid scratch_[2];
    std::vector<std::pair<int, int>> cutting_; // the cell's planes that cut (vertices cut off, plane index)
    std::vector<const PlacedCell*> hit_;       // scratch of cutPrimitive: the cells that cut the primitive
    std::vector<int> outer_;                   // scratch of cutPrimitive: the outer cells that may reach it
    std::deque<Solid> remainderParts_;         // scratch of cutRemainder: the parts (see there)
    std::vector<int> restParts_, nextParts_;   // scratch of cutRemainder: parts by index
    struct CellsOfPlane {
        int count = 0;
        int cell[2] = {-1, -1}; // the first two
    };
    std::vector<CellsOfPlane> cellsOfPlane_; // per pattern plane
    std::vector<int> clipRank_;     // per pattern cell: its place in the order cutPrimitive clips to cells
    std::vector<geometry::Aabb> cellBox_; // per pattern cell: its placed box
    std::vector<Solid> sides_;      // the current primitive beyond a plane it was split by first
    std::vector<int> sideKeys_;     // per side: that plane's key (PlacedCell::keys)
    int sideCount_ = 0;             // sides_ in use
    std::vector<int> cutList_; // the primitives a free cell clipped, ascending
    std::vector<int> cutPieces_; // the pieces that are cut (Piece::solid >= 0), ascending
    geometry::UnionFind islands_{0};
    std::vector<int> pieceIds_;                    // scratch of takeShape's callers (pieceIds)
    std::vector<int> pairCount_;                   // scratch of buildFragment's sortPairs
    std::vector<std::pair<int, int>> pairScratch_; // scratch of buildFragment's sortPairs
    std::vector<std::pair<int, int>> edges_;
    // Indices of the body's connections with an end not whole in the far region, ascending
    // (findIslands): with those of the whole far primitives the rest loses (assemble), every
    // connection the edited rest must look up.
    std::vector<int> touchedConnections_;
    bool connectionsSorted_ = false; // the body's connections are sorted by their first end (findIslands)
    bool merged_ = false;            // mergeSmallIslands joined some island to another
};

} // namespace

namespace {

void checkInputs(const geometry::PhysicalMesh& body, const FracturePattern& pattern, const Placement& where,
                 const CutSettings& settings) {
    settings.check(body.name);
    where.check(body.name);
    checkPattern(pattern, "body '" + body.name + "'");
}

} // namespace

FractureResult fractureMesh(const geometry::PhysicalMesh& body, const FracturePattern& pattern, const Placement& where,
                            const CutSettings& settings, const PrimitiveIndex& index) {
    checkInputs(body, pattern, where, settings);
    if (index.tree && index.tree->itemCount() != int(body.primitives.size()))
        throw InputError("body '" + body.name + "': a primitive index of " + std::to_string(index.tree->itemCount()) +
                         " items for " + std::to_string(body.primitives.size()) + " primitives");
    if (index.surface && !index.surface->fits(body))
        throw InputError("body '" + body.name + "': a surface index of " + std::to_string(index.surface->visualCount()) +
                         " visual vertices and " + std::to_string(index.surface->faceCount()) + " faces for " +
                         std::to_string(body.visual.positions.size()) + " and " + std::to_string(body.visual.faces.size()));
    return Fracturer(body, pattern, where, settings, index).run();
}

CutPieces cutMesh(const geometry::PhysicalMesh& body, const FracturePattern& pattern, const Placement& where,
                  const CutSettings& settings) {
    checkInputs(body, pattern, where, settings);
    return Fracturer(body, pattern, where, settings).cutOnly();
}

} // namespace shatter::fracture

