#pragma once
// Static bounding-volume tree over item boxes (primitives of a physical mesh).
// Built top-down by median split along the longest axis; refit() updates boxes
// in place when items move without changing the topology.
#include <shatter/plugin/geometry/Aabb.h>
#include <shatter/plugin/geometry/HoleFilling.h>
#include <shatter/plugin/geometry/StampedScratch.h>
#include <shatter/plugin/geometry/WalkStack.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <functional>
#include <tuple>
#include <utility>
#include <vector>

namespace shatter::geometry {

struct Aabb;
// Box enclosing `box` after a rigid motion.
Aabb transformedAabb(const Aabb& box, const Eigen::Isometry3d& t);

class AabbTree {
public:
    AabbTree() = default;
    // `spareNodes`: room for that many more nodes, so that removeAndAppend can add as many
    // without moving the node array (a move of a large tree writes all of it to fresh pages;
    // room never written costs no memory). The tree is the same with any room.
    explicit AabbTree(const std::vector<Aabb>& itemBoxes, size_t spareNodes = 0);
    // A copy of `other` with room for `spareNodes` more nodes.
    AabbTree(const AabbTree& other, size_t spareNodes);

    int itemCount() const { return itemCount_; }
    bool empty() const { return nodes_.empty(); }
    const Aabb& bounds() const { return nodes_[size_t(root_)].box; }

    // New boxes for the same items (same count and order as at construction).
    void refit(const std::vector<Aabb>& itemBoxes);
    // Grows every node's box by r >= 0 on every side. On a tree fresh from a build, the boxes
    // are bit for bit those refit() gives for the item boxes grown by r (x - r and x + r round
    // monotonically in x, so growing a union is uniting the grown boxes, and no zero of
    // another sign comes out). O(nodes), no child read. Throws std::invalid_argument if r < 0.
    void inflate(double r);

    // Drops the items whose newIndex is -1 and renumbers the others to newIndex (ascending
    // in the old order), then adds items for `appended` numbered after them: the kept part
    // keeps its shape (nodes left with one child are skipped, boxes shrink to what is left)
    // and the new items hang from the root in a tree of their own. One flat pass over the
    // nodes in place plus O(m log m) for m appended, where a build would be O(n log n).
    void removeAndAppend(const std::vector<int>& newIndex, const std::vector<Aabb>& appended);
    // The edit of geometry::fillHoles(itemCount(), removed, appended.size()) (`slots`): drops
    // the `removed` items (ascending), renumbers the survivors slots.moves moves, and adds
    // appended item j as item slots.addedAt[j]. The tree is the one removeAndAppend gives for
    // the same edit (same shape, same boxes, so the same answers in the same order), but only
    // the removed leaves' ancestors are visited: O((removed + moves) depth + m log m), plus a
    // byte per node zeroed (the visited marks), where
    // removeAndAppend passes over every node (a fracture's rest: ~550 of 16k items, ~2 M
    // instructions for a flat pass over both of its group shape's trees).
    void fillHoles(const std::vector<int>& removed, const HoleFilling& slots, const std::vector<Aabb>& appended);

    // Calls visit(item) for every item whose leaf box, and every box above it, passes
    // accept(box): a subtree is skipped at the first box that fails, so accept must fail for
    // a box whenever it fails for a box inside it (e.g. "overlaps a region"). Depth first, left
    // before right. A template, for callers that visit many items (no call through a
    // std::function per node).
    template <typename Accept, typename Visit>
    void search(const Accept& accept, const Visit& visit) const {
        search(0, [&accept](const Aabb& box, int&) { return accept(box); }, visit);
    }
    // The same, with a state handed down the tree: accept(box, state) starts from its
    // parent's state (`root` at the root) and may narrow it for the boxes below (a node's box
    // holds its children's), e.g. the planes a box lies wholly on one side of need no test below.
    template <typename State, typename Accept, typename Visit>
    void search(State root, const Accept& accept, const Visit& visit) const {
        if (nodes_.empty()) return;
        WalkStack<std::pair<int, State>> stack;
        stack.push({root_, root});
        while (!stack.empty()) {
            auto [index, state] = stack.pop();
            const Node& n = nodes_[size_t(index)];
            if (!accept(n.box, state)) continue;
            if (n.item >= 0) {
                visit(n.item);
            } else {
                stack.push({n.right, state});
                stack.push({n.left, state});
            }
        }
    }
    // A branch and bound for the largest value over the items (e.g. the farthest point): calls
    // visit(item) for the items whose leaf, and every node above it, has bound(box) > floor(),
    // where floor() is what the visits found so far (it may only rise) and bound(box) is at
    // least the value of every item below the box. The maximum over the visited items is then
    // the maximum over all items, whatever the order; the order is chosen to raise the floor
    // early: of a node's children, the one with the larger bound first (the other's bound is
    // kept and compared again when its turn comes, without reading its node).
    template <typename Bound, typename Floor, typename Visit>
    void searchLargestFirst(const Bound& bound, const Floor& floor, const Visit& visit) const {
        if (nodes_.empty()) return;
        WalkStack<std::pair<int, double>> stack;
        stack.push({root_, bound(nodes_[size_t(root_)].box)});
        while (!stack.empty()) {
            const auto [index, above] = stack.pop();
            if (!(above > floor())) continue;
            const Node& n = nodes_[size_t(index)];
            if (n.item >= 0) {
                visit(n.item);
                continue;
            }
            const double left = bound(nodes_[size_t(n.left)].box);
            const double right = bound(nodes_[size_t(n.right)].box);
            const bool leftFirst = left >= right;
            stack.push(leftFirst ? std::pair{n.right, right} : std::pair{n.left, left});
            stack.push(leftFirst ? std::pair{n.left, left} : std::pair{n.right, right});
        }
    }
    // Calls visit(item) for every item whose box overlaps `box`. A template, as search: a
    // group's leaves against a fragment visit one item per query node or two.
    template <typename Visit>
    void query(const Aabb& box, const Visit& visit) const {
        search([&box](const Aabb& b) { return b.overlaps(box); }, visit);
    }
    // Calls visit(item) for every item whose box may lie on the negative side of the
    // plane n·x = d + margin (box corner below it).
    void queryBelowPlane(const Eigen::Vector3d& n, double d, const std::function<void(int)>& visit) const;
    // Calls visit(a, b), a < b, for every pair of items whose boxes overlap. The order is the
    // recursive walk's: at a node against itself, its left child against itself, then the right
    // against itself, then left against right; at two overlapping nodes, the larger one's (the
    // longer extent sum; the first on a tie) left child then right child against the other. A
    // template walking an explicit stack: a soft body's self-contact list walks 4,900 items'
    // tree every few steps, and a recursive call through std::function per node pair was
    // most of that walk.
    template <typename Visit>
    void selfPairs(const Visit& visit) const {
        if (nodes_.size() <= 1) return;
        // The pair taken next is walked at once instead of pushed and popped: the first child
        // pair of a descent is the one the recursion takes next, the others wait on the stack.
        // Each node's extent sum (the descent's choice), once per node, not once per node pair
        // that meets it: a node of the sheet's tree meets a dozen others.
        std::vector<double> extentSum(nodes_.size());
        for (size_t i = 0; i < nodes_.size(); ++i) extentSum[i] = nodes_[i].box.extent().sum();
        WalkStack<std::pair<int, int>> pending;
        int a = root_, b = root_;
        for (;;) {
            const Node& na = nodes_[size_t(a)];
            if (a == b) {
                if (na.item < 0) {
                    pending.push({na.left, na.right});
                    pending.push({na.right, na.right});
                    a = b = na.left;
                    continue;
                }
            } else if (const Node& nb = nodes_[size_t(b)]; na.box.overlaps(nb.box)) {
                if (na.item >= 0 && nb.item >= 0) {
                    visit(std::min(na.item, nb.item), std::max(na.item, nb.item));
                } else if (nb.item >= 0 || (na.item < 0 && extentSum[size_t(a)] >= extentSum[size_t(b)])) {
                    pending.push({na.right, b});
                    a = na.left;
                    continue;
                } else {
                    pending.push({a, nb.right});
                    b = nb.left;
                    continue;
                }
            }
            if (pending.empty()) return;
            std::tie(a, b) = pending.pop();
        }
    }
    // Calls visit(a, b) for items a of this tree and b of `other` whose boxes overlap once
    // other's boxes are moved by otherToThis (conservatively: the moved box's AABB). visit must
    // not start another pairsWith on the thread: the walk's turned boxes are per-thread scratch.
    // A template: two groups lying on each other list a million pairs at a shrink.
    // `depth` (this tree's axes, none negative): only boxes that overlap by at least that much
    // (trees whose boxes were grown more than the caller needs). The pairs visited are then
    // some of those visited without it, in the same order: the descent does not depend on it.
    template <typename Visit>
    void pairsWith(const AabbTree& other, const Eigen::Isometry3d& otherToThis, const Visit& visit,
                   const Eigen::Vector3d& depth = Eigen::Vector3d::Zero()) const {
        if (nodes_.empty() || other.nodes_.empty()) return;
        // Each pop pushes at most two pairs, and every push goes one level deeper in one of the
        // trees, so the stack holds at most the two depths together.
        WalkStack<std::pair<int, int>, 256> stack;
        stack.push({root_, other.root_});
        TurnedBoxes turned(other, otherToThis);
        const bool deep = (depth.array() > 0).any();
        while (!stack.empty()) {
            const auto [a, b] = stack.pop();
            const Node& na = nodes_[size_t(a)];
            const Node& nb = other.nodes_[size_t(b)];
            if (!(deep ? overlapBy(na.box, turned[b], depth) : na.box.overlaps(turned[b]))) continue;
            const bool descendA = nb.item >= 0 || (na.item < 0 && na.box.extent().sum() >= nb.box.extent().sum());
            if (na.item >= 0 && nb.item >= 0) {
                visit(na.item, nb.item);
            } else if (descendA) {
                stack.push({na.right, b});
                stack.push({na.left, b});
            } else {
                stack.push({a, nb.right});
                stack.push({a, nb.left});
            }
        }
    }

private:
    // Whether a and b overlap by at least `depth` along every axis.
    static bool overlapBy(const Aabb& a, const Aabb& b, const Eigen::Vector3d& depth) {
        return ((b.max - a.min).array() >= depth.array()).all() && ((a.max - b.min).array() >= depth.array()).all();
    }
    // Each node box of `other` turned into this tree's frame: a node of `other` is met with many
    // of this tree's, so its box is turned once per walk, when first met (StampedScratch).
    class TurnedBoxes {
    public:
        TurnedBoxes(const AabbTree& other, const Eigen::Isometry3d& otherToThis)
            : other_(other), otherToThis_(otherToThis), boxes_(other.nodes_.size()) {}
        const Aabb& operator[](int node) {
            return boxes_.get(size_t(node), [&] { return transformedAabb(other_.nodes_[size_t(node)].box, otherToThis_); });
        }

    private:
        const AabbTree& other_;
        const Eigen::Isometry3d& otherToThis_;
        StampedScratch<Aabb> boxes_;
    };

    struct Node {
        Aabb box;
        int left = -1;  // child node, or -1 for a leaf
        int right = -1;
        int item = -1;  // leaf item
        int parent = -1; // -1 for the root (and for nodes no longer in the tree)
    };
    static constexpr int kDead = -2; // item of a node with no item left under it (removeAndAppend, fillHoles)

    // keys[3 i + axis]: item i's min[axis] + max[axis] (its centre times two).
    int build(std::vector<int>& items, int begin, int end, const std::vector<Aabb>& boxes,
              const std::vector<double>& keys);
    // A tree of k items has 2k - 1 live nodes.
    static size_t liveNodes(int items) { return items > 0 ? 2 * size_t(items) - 1 : 0; }
    // Drops the nodes the root no longer reaches.
    void compact();
    int copyLive(const std::vector<Node>& old, int node);
    // Adds a tree over `appended` (item j numbered itemOf(j)) beside the root.
    template <typename ItemOf>
    void append(const std::vector<Aabb>& appended, const ItemOf& itemOf);
    // Makes `child` (a node or -1 for none) the child of `parent` and, at a leaf, its item's leaf.
    void link(int parent, int child);

    // Every node after its children (built bottom-up), so passes over the array run upwards.
    std::vector<Node> nodes_;
    int root_ = 0;
    int itemCount_ = 0;
    std::vector<int> leafOf_; // per item: its leaf node (with the nodes' parents, fillHoles' way up)
};

} // namespace shatter::geometry
