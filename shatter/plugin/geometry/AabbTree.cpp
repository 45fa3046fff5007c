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

AabbTree::AabbTree(const std::vector<Aabb>& itemBoxes) : itemCount_(int(itemBoxes.size())) {
    if (itemBoxes.empty()) return;
    std::vector<int> items(itemBoxes.size());
    for (size_t i = 0; i < items.size(); ++i) items[i] = int(i);
    nodes_.reserve(2 * items.size());
    build(items, 0, int(items.size()), itemBoxes);
}

int AabbTree::build(std::vector<int>& items, int begin, int end, const std::vector<Aabb>& boxes) {
    const int index = int(nodes_.size());
    nodes_.emplace_back();
    Aabb box;
    for (int i = begin; i < end; ++i) box.extend(boxes[items[i]]);
    nodes_[index].box = box;
    if (end - begin == 1) {
        nodes_[index].item = items[begin];
        return index;
    }
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
    const int left = build(items, begin, mid, boxes);
    const int right = build(items, mid, end, boxes);
    nodes_[index].left = left;
    nodes_[index].right = right;
    return index;
}

void AabbTree::refit(const std::vector<Aabb>& itemBoxes) {
    if (!nodes_.empty()) refitNode(0, itemBoxes);
}

void AabbTree::refitNode(int node, const std::vector<Aabb>& boxes) {
    Node& n = nodes_[node];
    if (n.item >= 0) {
        n.box = boxes[n.item];
        return;
    }
    refitNode(n.left, boxes);
    refitNode(n.right, boxes);
    nodes_[node].box = nodes_[nodes_[node].left].box;
    nodes_[node].box.extend(nodes_[nodes_[node].right].box);
}

void AabbTree::removeAndAppend(const std::vector<int>& newIndex, const std::vector<Aabb>& appended) {
    std::vector<Node> old = std::move(nodes_);
    nodes_.clear();
    nodes_.reserve(old.size() + 2 * appended.size() + 1);
    std::vector<char> kept(old.size(), 0);
    const bool anyKept = !old.empty() && markKept(old, 0, newIndex, kept);
    int keptCount = 0;
    for (int i : newIndex) keptCount += i >= 0;
    const AabbTree extra(appended);
    auto graft = [&] { // extra's nodes after ours, items numbered after the kept ones
        const int offset = int(nodes_.size());
        for (Node n : extra.nodes_) {
            if (n.item >= 0) n.item += keptCount;
            else {
                n.left += offset;
                n.right += offset;
            }
            nodes_.push_back(n);
        }
        return offset;
    };
    if (anyKept && !extra.empty()) {
        nodes_.emplace_back(); // the root joins the kept tree and the new one
        const int left = copyKept(old, 0, newIndex, kept);
        const int right = graft();
        nodes_[0].left = left;
        nodes_[0].right = right;
        nodes_[0].box = nodes_[size_t(left)].box;
        nodes_[0].box.extend(nodes_[size_t(right)].box);
    } else if (anyKept) {
        copyKept(old, 0, newIndex, kept);
    } else if (!extra.empty()) {
        graft();
    }
    itemCount_ = keptCount + int(appended.size());
}

bool AabbTree::markKept(const std::vector<Node>& old, int node, const std::vector<int>& newIndex,
                        std::vector<char>& kept) const {
    const Node& n = old[size_t(node)];
    const bool any = n.item >= 0 ? newIndex[size_t(n.item)] >= 0
                                 : (markKept(old, n.left, newIndex, kept) | markKept(old, n.right, newIndex, kept));
    kept[size_t(node)] = any;
    return any;
}

int AabbTree::copyKept(const std::vector<Node>& old, int node, const std::vector<int>& newIndex,
                       const std::vector<char>& kept) {
    const Node& n = old[size_t(node)];
    if (n.item >= 0) {
        nodes_.push_back({n.box, -1, -1, newIndex[size_t(n.item)]});
        return int(nodes_.size()) - 1;
    }
    // A node left with one child is that child.
    if (!kept[size_t(n.left)]) return copyKept(old, n.right, newIndex, kept);
    if (!kept[size_t(n.right)]) return copyKept(old, n.left, newIndex, kept);
    const int index = int(nodes_.size());
    nodes_.emplace_back();
    const int left = copyKept(old, n.left, newIndex, kept);
    const int right = copyKept(old, n.right, newIndex, kept);
    Node& copy = nodes_[size_t(index)];
    copy.left = left;
    copy.right = right;
    copy.box = nodes_[size_t(left)].box;
    copy.box.extend(nodes_[size_t(right)].box);
    return index;
}

// Depth-first walk over the nodes whose boxes `accept` keeps, visiting the items of the leaves.
template <typename Accept>
void AabbTree::descend(const Accept& accept, const std::function<void(int)>& visit) const {
    if (nodes_.empty()) return;
    int stack[128]; // deeper than any median-split tree of addressable size
    int top = 0;
    stack[top++] = 0;
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
    if (nodes_.size() > 1) selfPairs(0, 0, visit);
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
    stack[top++] = {0, 0};
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
