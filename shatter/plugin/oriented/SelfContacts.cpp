#include <shatter/plugin/oriented/SelfContacts.h>

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

void addSelfContacts(const std::vector<geometry::ConvexPolyhedron>& primitives, const geometry::AabbTree& tree,
                     const ShapeMatchingGroups& groups, double reach, double friction,
                     std::vector<ParticleContact>& contacts) {
    tree.selfPairs([&](int a, int b) {
        if (groups.connected(a, b)) return;
        const PrimitiveSeparation s = separationUpTo(primitives[size_t(a)], primitives[size_t(b)], reach);
        if (s.distance > reach) return;
        ParticleContact c;
        c.particle = a;
        c.otherParticle = b;
        c.normal = s.normal;
        c.distance = s.distance;
        c.friction = friction;
        contacts.push_back(c);
    });
}

} // namespace shatter::oriented
