#include <shatter/plugin/geometry/AabbTree.h>

#include <algorithm>
#include <array>
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
    root_ = build(items, 0, int(items.size()), itemBoxes);
}

AabbTree::AabbTree(const AabbTree& other, size_t spareNodes) : root_(other.root_), itemCount_(other.itemCount_) {
    nodes_.reserve(other.nodes_.size() + spareNodes);
    nodes_ = other.nodes_; // into the room reserved: no second allocation
}

int AabbTree::build(std::vector<int>& items, int begin, int end, const std::vector<Aabb>& boxes) {
    Node node;
    if (end - begin == 1) {
        node.box = boxes[items[begin]];
        node.item = items[begin];
    } else {
        // Split at the median centre along the axis where the centres spread most.
        Aabb centres;
        for (int i = begin; i < end; ++i) centres.extend(boxes[items[i]].center());
        int axis = 0;
        centres.extent().maxCoeff(&axis);
        const int mid = (begin + end) / 2;
        std::nth_element(items.begin() + begin, items.begin() + mid, items.begin() + end, [&](int a, int b) {
            const double ca = boxes[a].min[axis] + boxes[a].max[axis];
            const double cb = boxes[b].min[axis] + boxes[b].max[axis];
            return ca < cb || (ca == cb && a < b); // index tie-break keeps builds deterministic
        });
        node.left = build(items, begin, mid, boxes);
        node.right = build(items, mid, end, boxes);
        node.box = nodes_[node.left].box;
        node.box.extend(nodes_[node.right].box);
    }
    nodes_.push_back(node); // after its children: see nodes_
    return int(nodes_.size()) - 1;
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

void AabbTree::removeAndAppend(const std::vector<int>& newIndex, const std::vector<Aabb>& appended,
                               const std::vector<int>* appendedIndex) {
    // One pass upwards over the nodes, in place (children come first): kept leaves take their
    // new index, a node with one child left becomes (a copy of) that child, a node with none
    // is dead; boxes shrink to what is left. The copied-from and dead nodes stay behind,
    // unreachable, until they outnumber the live ones.
    for (Node& n : nodes_) {
        if (n.left < 0) {
            if (n.item >= 0) n.item = newIndex[size_t(n.item)] >= 0 ? newIndex[size_t(n.item)] : kDead;
            continue;
        }
        const bool leftDead = nodes_[n.left].item == kDead, rightDead = nodes_[n.right].item == kDead;
        if (leftDead && rightDead) n = Node{Aabb{}, -1, -1, kDead};
        else if (leftDead) n = nodes_[n.right];
        else if (rightDead) n = nodes_[n.left];
        else {
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
    if (appended.empty()) return;
    // The new items in a tree of their own (items numbered after the kept ones) under a new
    // root beside the kept part.
    const AabbTree extra(appended);
    const int offset = int(nodes_.size());
    for (Node n : extra.nodes_) {
        if (n.left < 0) n.item = appendedIndex ? (*appendedIndex)[size_t(n.item)] : n.item + keptCount;
        else {
            n.left += offset;
            n.right += offset;
        }
        nodes_.push_back(n);
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
}

void AabbTree::compact() {
    std::vector<Node> old;
    old.swap(nodes_);
    nodes_.reserve(old.size() / 2 + 1);
    root_ = copyLive(old, root_);
}

int AabbTree::copyLive(const std::vector<Node>& old, int node) {
    Node n = old[size_t(node)];
    if (n.left >= 0) {
        n.left = copyLive(old, n.left);
        n.right = copyLive(old, n.right);
    }
    nodes_.push_back(n);
    return int(nodes_.size()) - 1;
}

// Depth-first walk over the nodes whose boxes `accept` keeps, visiting the items of the leaves.
template <typename Accept>
void AabbTree::descend(const Accept& accept, const std::function<void(int)>& visit) const {
    if (nodes_.empty()) return;
    int stack[128]; // deeper than any median-split tree of addressable size
    int top = 0;
    stack[top++] = root_;
    while (top > 0) {
        const Node& n = nodes_[stack[--top]];
        if (!accept(n.box)) continue;
        if (n.item >= 0) {
            visit(n.item);
        } else {
            stack[top++] = n.right;
            stack[top++] = n.left;
        }
    }
}

void AabbTree::query(const Aabb& box, const std::function<void(int)>& visit) const {
    descend([&box](const Aabb& b) { return b.overlaps(box); }, visit);
}

void AabbTree::queryBelowPlane(const Eigen::Vector3d& normal, double d, const std::function<void(int)>& visit) const {
    descend(
        [&](const Aabb& b) {
            // Lowest corner of the box along the normal.
            const Eigen::Vector3d corner = (normal.array() >= 0.0).select(b.min, b.max);
            return normal.dot(corner) <= d;
        },
        visit);
}

void AabbTree::selfPairs(const std::function<void(int, int)>& visit) const {
    if (nodes_.size() > 1) selfPairs(root_, root_, visit);
}

void AabbTree::selfPairs(int a, int b, const std::function<void(int, int)>& visit) const {
    const Node& na = nodes_[a];
    const Node& nb = nodes_[b];
    if (a == b) {
        if (na.item >= 0) return;
        selfPairs(na.left, na.left, visit);
        selfPairs(na.right, na.right, visit);
        selfPairs(na.left, na.right, visit);
        return;
    }
    if (!na.box.overlaps(nb.box)) return;
    if (na.item >= 0 && nb.item >= 0) {
        visit(std::min(na.item, nb.item), std::max(na.item, nb.item));
    } else if (nb.item >= 0 || (na.item < 0 && na.box.extent().sum() >= nb.box.extent().sum())) {
        selfPairs(na.left, b, visit);
        selfPairs(na.right, b, visit);
    } else {
        selfPairs(a, nb.left, visit);
        selfPairs(a, nb.right, visit);
    }
}

void AabbTree::pairsWith(const AabbTree& other, const Eigen::Isometry3d& otherToThis,
                         const std::function<void(int, int)>& visit) const {
    if (nodes_.empty() || other.nodes_.empty()) return;
    // Each pop pushes at most two pairs, and every push goes one level deeper in one of the
    // trees, so the stack never holds more than the two depths together (< 2 × 128).
    std::array<std::pair<int, int>, 256> stack;
    int top = 0;
    stack[top++] = {root_, other.root_};
    while (top > 0) {
        const auto [a, b] = stack[--top];
        const Node& na = nodes_[a];
        const Node& nb = other.nodes_[b];
        if (!na.box.overlaps(transformedAabb(nb.box, otherToThis))) continue;
        const bool descendA = nb.item >= 0 || (na.item < 0 && na.box.extent().sum() >= nb.box.extent().sum());
        if (na.item >= 0 && nb.item >= 0) {
            visit(na.item, nb.item);
        } else if (descendA) {
            stack[top++] = {na.right, b};
            stack[top++] = {na.left, b};
        } else {
            stack[top++] = {a, nb.right};
            stack[top++] = {a, nb.left};
        }
    }
}

} // namespace shatter::geometry
