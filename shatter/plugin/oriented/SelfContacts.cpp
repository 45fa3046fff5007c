#include <shatter/plugin/oriented/SelfContacts.h>

#include <algorithm>
#include <limits>

namespace shatter::oriented {

namespace {

// The largest separation of `other` beyond one of `faces`' planes (its vertices' lowest
// distance above the plane), and that plane's normal; stops at the first beyond `enough`.
PrimitiveSeparation beyondFaces(const geometry::ConvexPolyhedron& faces, const geometry::ConvexPolyhedron& other,
                                double enough) {
    PrimitiveSeparation best{-std::numeric_limits<double>::infinity(), Eigen::Vector3d::UnitZ()};
    for (const geometry::Plane& plane : faces.planes()) {
        double lowest = std::numeric_limits<double>::infinity();
        for (const Eigen::Vector3d& v : other.vertices()) lowest = std::min(lowest, plane.signedDistance(v));
        if (lowest > best.distance) best = {lowest, plane.normal};
        if (best.distance > enough) break;
    }
    return best;
}

// faceSeparation, but any answer beyond `enough` may be any separation beyond it.
PrimitiveSeparation separationUpTo(const geometry::ConvexPolyhedron& a, const geometry::ConvexPolyhedron& b,
                                   double enough) {
    PrimitiveSeparation alongA = beyondFaces(a, b, enough); // b beyond a's face: a is pushed against its normal
    alongA.normal = -alongA.normal;
    if (alongA.distance > enough) return alongA;
    const PrimitiveSeparation alongB = beyondFaces(b, a, enough); // a beyond b's face: pushed along it
    return alongB.distance > alongA.distance ? alongB : alongA;
}

} // namespace

PrimitiveSeparation faceSeparation(const geometry::ConvexPolyhedron& a, const geometry::ConvexPolyhedron& b) {
    return separationUpTo(a, b, std::numeric_limits<double>::infinity());
}

void addSelfContacts(const std::vector<geometry::ConvexPolyhedron>& primitives, const ShapeMatchingGroups& groups,
                     double reach, double friction, std::vector<ParticleContact>& contacts) {
    // Sort and sweep along the axis where the boxes' centres spread most: a pair's boxes can
    // overlap only if their intervals on it do, and each box meets the few boxes that start
    // inside its interval. Cheaper than a tree walk here, where almost every overlapping
    // pair is a connected neighbour that is dropped anyway.
    const int n = int(primitives.size());
    const size_t before = contacts.size();
    Eigen::Vector3d mean = Eigen::Vector3d::Zero(), square = Eigen::Vector3d::Zero();
    for (const auto& p : primitives) {
        const Eigen::Vector3d c = p.bounds().center();
        mean += c;
        square += c.cwiseProduct(c);
    }
    int axis = 0;
    (square - mean.cwiseProduct(mean) / std::max(n, 1)).maxCoeff(&axis);
    // The boxes in sweep order, contiguous; the sort moves (low end, primitive) pairs only.
    std::vector<std::pair<double, int>> order(static_cast<size_t>(n));
    for (int i = 0; i < n; ++i) order[size_t(i)] = {primitives[size_t(i)].bounds().min[axis], i};
    std::sort(order.begin(), order.end());
    std::vector<geometry::Aabb> boxes(static_cast<size_t>(n));
    for (int u = 0; u < n; ++u) boxes[size_t(u)] = primitives[size_t(order[size_t(u)].second)].bounds();
    for (size_t u = 0; u < boxes.size(); ++u) {
        const geometry::Aabb& box = boxes[u];
        for (size_t v = u + 1; v < boxes.size() && boxes[v].min[axis] <= box.max[axis]; ++v) {
            if (!box.overlaps(boxes[v])) continue;
            const int a = std::min(order[u].second, order[v].second);
            const int b = std::max(order[u].second, order[v].second);
            if (groups.connected(a, b)) continue;
            const PrimitiveSeparation s = separationUpTo(primitives[size_t(a)], primitives[size_t(b)], reach);
            if (s.distance > reach) continue;
            ParticleContact c;
            c.particle = a;
            c.otherParticle = b;
            c.normal = s.normal;
            c.distance = s.distance;
            c.friction = friction;
            contacts.push_back(c);
        }
    }
    // In pair order, whatever the sweep's axis: the projection is Gauss-Seidel, so the order
    // of the contacts is part of the result.
    std::sort(contacts.begin() + long(before), contacts.end(), [](const ParticleContact& x, const ParticleContact& y) {
        return std::pair(x.particle, x.otherParticle) < std::pair(y.particle, y.otherParticle);
    });
}

} // namespace shatter::oriented
