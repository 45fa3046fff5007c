#include <shatter/plugin/geometry/AabbTree.h>

#include <shatter/plugin/common/Prefetch.h>

#include <algorithm>
#include <stdexcept>
#include <string>
#include <utility>

namespace shatter::geometry {

Aabb transformedAabb(const Aabb& box, const Eigen::Isometry3d& t) {
    const Eigen::Vector3d c = t * box.center();
    const Eigen::Vector3d h = t.linear().cwiseAbs() * (0.5 * box.extent());
    return {c - h, c + h};
}

AabbTree::AabbTree(const std::vector<Aabb>& itemBoxes, size_t spareNodes) : itemCount_(int(itemBoxes.size())) {
    if (itemBoxes.empty()) return;
    std::vector<int> items(itemBoxes.size());
    for (size_t i = 0; i < items.size(); ++i) items[i] = int(i);
    nodes_.reserve(2 * items.size() + spareNodes);
    leafOf_.resize(items.size());
    // Each item's centre sums min + max per axis, computed once: the median searches compare
    // them ~n log n times, each time loading both corners through the item's box (measured:
    // build was 8.5 M of the 276.6 M instructions of five 64-cell events of the 16k shell).
    std::vector<double> keys(3 * items.size());
    for (size_t i = 0; i < items.size(); ++i)
        for (int axis = 0; axis < 3; ++axis) keys[3 * i + size_t(axis)] = itemBoxes[i].min[axis] + itemBoxes[i].max[axis];
    root_ = build(items, 0, int(items.size()), itemBoxes, keys);
}

AabbTree::AabbTree(const AabbTree& other, size_t spareNodes)
    : root_(other.root_), itemCount_(other.itemCount_), leafOf_(other.leafOf_) {
    nodes_.reserve(other.nodes_.size() + spareNodes);
    nodes_ = other.nodes_; // into the room reserved: no second allocation
}

void AabbTree::link(int parent, int child) {
    nodes_[size_t(child)].parent = parent;
    if (nodes_[size_t(child)].item >= 0) leafOf_[size_t(nodes_[size_t(child)].item)] = child;
}

int AabbTree::build(std::vector<int>& items, int begin, int end, const std::vector<Aabb>& boxes,
                    const std::vector<double>& keys) {
    Node node;
    if (end - begin == 1) {
        node.box = boxes[items[begin]];
        node.item = items[begin];
    } else {
        // Split at the median centre along the axis where the centres spread most. A centre is
        // 0.5 * (min + max), its key times 0.5: the same values as from the boxes.
        Aabb centres;
        for (int i = begin; i < end; ++i) {
            const double* k = &keys[3 * size_t(items[i])];
            centres.extend(Eigen::Vector3d(0.5 * k[0], 0.5 * k[1], 0.5 * k[2]));
        }
        int axis = 0;
        centres.extent().maxCoeff(&axis);
        const int mid = (begin + end) / 2;
        // The keys of the axis are min + max as before, so every comparison and the
        // permutation nth_element leaves (hence the tree) are the same.
        const double* key = keys.data() + axis;
        auto before = [key](int a, int b) {
            const double ca = key[3 * size_t(a)];
            const double cb = key[3 * size_t(b)];
            return ca < cb || (ca == cb && a < b); // index tie-break keeps builds deterministic
        };
        // Two items (about half the inner nodes of a fragment's tree): the smaller first, as
        // nth_element leaves them, without its call.
        if (end - begin == 2) {
            if (before(items[begin + 1], items[begin])) std::swap(items[begin], items[begin + 1]);
        } else {
            std::nth_element(items.begin() + begin, items.begin() + mid, items.begin() + end, before);
        }
        node.left = build(items, begin, mid, boxes, keys);
        node.right = build(items, mid, end, boxes, keys);
        node.box = nodes_[node.left].box;
        node.box.extend(nodes_[node.right].box);
    }
    nodes_.push_back(node); // after its children: see nodes_
    const int at = int(nodes_.size()) - 1;
    if (node.left >= 0) {
        link(at, node.left);
        link(at, node.right);
    } else {
        link(-1, at);
    }
    return at;
}

void AabbTree::refit(const std::vector<Aabb>& itemBoxes) {
    // Children come first, so one pass upwards; nodes no longer reachable refit harmlessly.
    for (Node& n : nodes_) {
        if (n.left < 0) {
            if (n.item >= 0) n.box = itemBoxes[n.item];
            continue;
        }
        n.box = nodes_[n.left].box;
        n.box.extend(nodes_[n.right].box);
    }
}

void AabbTree::inflate(double r) {
    if (!(r >= 0.0)) throw std::invalid_argument("AabbTree::inflate: the growth must be >= 0, got " + std::to_string(r));
    for (Node& n : nodes_) n.box = n.box.inflated(r);
}

void AabbTree::removeAndAppend(const std::vector<int>& newIndex, const std::vector<Aabb>& appended) {
    // One pass upwards over the nodes, in place (children come first): kept leaves take their
    // new index, a node with one child left becomes (a copy of) that child, a node with none
    // is dead, and so is the node copied from; boxes shrink to what is left. Dead nodes stay
    // behind, unreachable, until they outnumber the live ones. A copy keeps its own parent and
    // becomes its new children's (or its item's leaf): the last copy, the one reached, wins.
    for (size_t i = 0; i < nodes_.size(); ++i) {
        Node& n = nodes_[i];
        if (n.left < 0) {
            if (n.item >= 0) {
                n.item = newIndex[size_t(n.item)] >= 0 ? newIndex[size_t(n.item)] : kDead;
                if (n.item >= 0) leafOf_[size_t(n.item)] = int(i);
            }
            continue;
        }
        const bool leftDead = nodes_[n.left].item == kDead, rightDead = nodes_[n.right].item == kDead;
        if (leftDead && rightDead) {
            n = Node{Aabb{}, -1, -1, kDead};
        } else if (leftDead || rightDead) {
            const int parent = n.parent, child = leftDead ? n.right : n.left;
            n = nodes_[size_t(child)];
            // The copied-from node is dead: a leaf left behind would keep an item number that
            // fillHoles later gives to another item (and refit would read its box).
            nodes_[size_t(child)] = Node{Aabb{}, -1, -1, kDead};
            if (n.left >= 0) {
                link(int(i), n.left);
                link(int(i), n.right);
            }
            link(parent, int(i));
        } else {
            n.box = nodes_[n.left].box;
            n.box.extend(nodes_[n.right].box);
        }
    }
    const bool anyKept = !nodes_.empty() && nodes_[root_].item != kDead;
    int keptCount = 0;
    for (int i : newIndex) keptCount += i >= 0;
    if (!anyKept) nodes_.clear();
    if (anyKept && 2 * liveNodes(keptCount) < nodes_.size()) compact();
    itemCount_ = keptCount + int(appended.size());
    leafOf_.resize(size_t(std::max(itemCount_, int(newIndex.size()))));
    append(appended, [&](int j) { return j + keptCount; });
    leafOf_.resize(size_t(itemCount_));
}

namespace {

// The helpers below are templates over the node type only to reach AabbTree's private Node
// without a header change. Hints alone, so inlined by force (see Prefetch.h).

// A hint to load node i (64 bytes, two cache lines when the array is 16-aligned). (A hint for a
// write, prefetchw, needs -mprfchw: without it GCC emits none.)
template <class Node>
[[gnu::always_inline]] inline void prefetchNode(const std::vector<Node>& nodes, int i) {
    if (i >= 0) prefetchRange(&nodes[size_t(i)], sizeof(Node));
}

// Before fillHoles removes `removed[k]`, hints for the removals after it: the leaf of the one
// kAhead * 3 on, the parent of the one kAhead * 2 on, the grandparent of the one kAhead on, each
// read from lines the earlier hints loaded. A removal reads these three nodes one after the
// other, all over a 16k-leaf tree's 2 MB: in perf (16k shell x 64 cells) two thirds of
// fillHoles' own time was that chain's misses. The values read here only choose what is
// loaded (removals in between may change them); the removal reads them again.
template <class Node>
[[gnu::always_inline]] inline void prefetchRemovals(const std::vector<Node>& nodes, const std::vector<int>& leafOf,
                                                    const std::vector<int>& removed, size_t k) {
    // 4, 8 and 12 were within noise of each other; at 8 perf's annotation still showed stalls.
    constexpr size_t kAhead = 12;
    const size_t n = removed.size();
    auto leaf = [&](size_t j) { return leafOf[size_t(removed[j])]; };
    if (k + 4 * kAhead < n) prefetchRange(&leafOf[size_t(removed[k + 4 * kAhead])], sizeof(int));
    if (k + 3 * kAhead < n) prefetchNode(nodes, leaf(k + 3 * kAhead));
    if (k + 2 * kAhead < n) prefetchNode(nodes, nodes[size_t(leaf(k + 2 * kAhead))].parent);
    if (k + kAhead >= n) return;
    const int parent = nodes[size_t(leaf(k + kAhead))].parent;
    if (parent >= 0) prefetchNode(nodes, nodes[size_t(parent)].parent);
}

// fillHoles' removals: each removed leaf and its parent die (item `dead`), the sibling takes
// the parent's place under the grandparent (or becomes the root). Returns the grandparents, whose
// boxes shrank.
template <class Node>
std::vector<int> unlinkLeaves(std::vector<Node>& nodes, const std::vector<int>& leafOf, const std::vector<int>& removed,
                              int& root, int dead) {
    std::vector<int> shrunk;
    shrunk.reserve(removed.size());
    for (size_t k = 0; k < removed.size(); ++k) {
        prefetchRemovals(nodes, leafOf, removed, k);
        const int leaf = leafOf[size_t(removed[k])];
        const int parent = nodes[size_t(leaf)].parent; // a survivor is left, so not the root
        Node& p = nodes[size_t(parent)];
        const int sibling = p.left == leaf ? p.right : p.left;
        const int grand = p.parent;
        nodes[size_t(leaf)] = Node{Aabb{}, -1, -1, dead};
        p = Node{Aabb{}, -1, -1, dead};
        nodes[size_t(sibling)].parent = grand;
        if (grand < 0) {
            root = sibling;
            continue;
        }
        Node& g = nodes[size_t(grand)];
        (g.left == parent ? g.left : g.right) = sibling;
        shrunk.push_back(grand);
    }
    return shrunk;
}

// The boxes of the live ancestors of `shrunk` (nodes and theirs), each once, bottom-up
// (children come first in `nodes`). An ancestor met is marked by item `marked` (inner nodes'
// item is -1) until its refit, not in an array over every node (zeroed at each call); a node
// recorded and removed later (dead) has its live ancestors recorded by that removal.
template <class Node>
void refitAncestors(std::vector<Node>& nodes, const std::vector<int>& shrunk, int dead, int marked) {
    std::vector<int> refit;
    for (const int s : shrunk)
        for (int k = s; k >= 0 && nodes[size_t(k)].item != dead && nodes[size_t(k)].item != marked;
             k = nodes[size_t(k)].parent) {
            nodes[size_t(k)].item = marked;
            refit.push_back(k);
        }
    std::sort(refit.begin(), refit.end());
    for (int k : refit) {
        Node& n = nodes[size_t(k)];
        n.box = nodes[size_t(n.left)].box;
        n.box.extend(nodes[size_t(n.right)].box);
        n.item = -1;
    }
}

} // namespace

void AabbTree::fillHoles(const std::vector<int>& removed, const HoleFilling& slots, const std::vector<Aabb>& appended) {
    // Each removed leaf takes its parent with it: the sibling hangs from the grandparent in
    // the parent's place (what removeAndAppend's copy of the one child left amounts to), and
    // the grandparent's box and those above it shrink. Boxes are refitted once, bottom-up
    // (children come first in nodes_), for the union of those ancestors only.
    const int keptCount = itemCount_ - int(removed.size());
    leafOf_.resize(size_t(std::max(itemCount_, slots.size)));
    if (keptCount == 0) {
        nodes_.clear();
    } else {
        constexpr int kMarked = kDead - 1; // an ancestor met, until its refit (refitAncestors)
        refitAncestors(nodes_, unlinkLeaves(nodes_, leafOf_, removed, root_, kDead), kDead, kMarked);
        for (size_t k = 0; k < slots.moves.size(); ++k) {
            const auto [from, to] = slots.moves[k];
            const int leaf = leafOf_[size_t(from)];
            nodes_[size_t(leaf)].item = to;
            leafOf_[size_t(to)] = leaf;
        }
        if (2 * liveNodes(keptCount) < nodes_.size()) compact();
    }
    itemCount_ = slots.size;
    append(appended, [&](int j) { return slots.addedAt[size_t(j)]; });
    leafOf_.resize(size_t(itemCount_));
}

template <typename ItemOf>
void AabbTree::append(const std::vector<Aabb>& appended, const ItemOf& itemOf) {
    if (appended.empty()) return;
    // The new items in a tree of their own under a new root beside the kept part (if any).
    const bool anyKept = !nodes_.empty();
    const AabbTree extra(appended);
    const int offset = int(nodes_.size());
    for (Node n : extra.nodes_) {
        if (n.left < 0) n.item = itemOf(n.item);
        else {
            n.left += offset;
            n.right += offset;
        }
        if (n.parent >= 0) n.parent += offset;
        nodes_.push_back(n);
        if (n.left < 0) link(n.parent, int(nodes_.size()) - 1);
    }
    if (!anyKept) {
        root_ = extra.root_ + offset;
        return;
    }
    Node join;
    join.left = root_;
    join.right = extra.root_ + offset;
    join.box = nodes_[join.left].box;
    join.box.extend(nodes_[join.right].box);
    nodes_.push_back(join);
    root_ = int(nodes_.size()) - 1;
    link(root_, join.left);
    link(root_, join.right);
}

void AabbTree::compact() {
    std::vector<Node> old;
    old.swap(nodes_);
    nodes_.reserve(old.size() / 2 + 1);
    root_ = copyLive(old, root_);
    link(-1, root_);
}

int AabbTree::copyLive(const std::vector<Node>& old, int node) {
    Node n = old[size_t(node)];
    if (n.left >= 0) {
        n.left = copyLive(old, n.left);
        n.right = copyLive(old, n.right);
    }
    nodes_.push_back(n);
    const int at = int(nodes_.size()) - 1;
    if (n.left >= 0) {
        link(at, n.left);
        link(at, n.right);
    }
    return at;
}

void AabbTree::queryBelowPlane(const Eigen::Vector3d& normal, double d, const std::function<void(int)>& visit) const {
    search(
        [&](const Aabb& b) {
            // Lowest corner of the box along the normal.
            const Eigen::Vector3d corner = (normal.array() >= 0.0).select(b.min, b.max);
            return normal.dot(corner) <= d;
        },
        visit);
}

} // namespace shatter::geometry
