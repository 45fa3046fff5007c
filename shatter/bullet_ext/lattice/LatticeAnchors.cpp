#include <shatter/bullet_ext/lattice/LatticeAnchors.h>

#include <shatter/bullet_ext/Convert.h>
#include <shatter/bullet_ext/lattice/LatticeBody.h>
#include <shatter/plugin/common/InputError.h>
#include <shatter/plugin/lattice/AnchorRegion.h>

#include <BulletCollision/CollisionShapes/btConvexHullShape.h>

#include <algorithm>
#include <sstream>

namespace shatter {

namespace {

// The tet is inflated by the distance (its collision margin), so a tet within the distance of
// the body overlaps it, and a tet touching it exactly (a corner on the ground: distance 0) is a
// shallow overlap rather than a tie that rounding could decide either way.
struct Touch : btCollisionWorld::ContactResultCallback {
    explicit Touch(double distance) : slack(btScalar(0.01 * distance)) { m_closestDistanceThreshold = btScalar(distance); }
    btScalar addSingleResult(btManifoldPoint& point, const btCollisionObjectWrapper*, int, int, const btCollisionObjectWrapper*, int,
                             int) override {
        touched = touched || point.getDistance() <= slack;
        return 0;
    }
    btScalar slack;
    bool touched = false;
};

} // namespace

std::vector<int> tetsTouching(const lattice::TetMesh& mesh, const btTransform& pose, const btCollisionObject& anchor,
                              double distance, btCollisionWorld& world) {
    btVector3 lo, hi;
    anchor.getCollisionShape()->getAabb(anchor.getWorldTransform(), lo, hi);
    const btScalar pad = btScalar(distance);
    lo -= btVector3(pad, pad, pad), hi += btVector3(pad, pad, pad);
    std::vector<int> out;
    for (int t = 0; t < int(mesh.tets.size()); ++t) {
        btVector3 corners[4];
        for (int k = 0; k < 4; ++k) corners[k] = pose * toBullet(mesh.nodes[mesh.tets[t][k]]);
        btVector3 tlo = corners[0], thi = corners[0];
        for (const btVector3& c : corners) tlo.setMin(c), thi.setMax(c);
        if (!TestAabbAgainstAabb2(tlo, thi, lo, hi)) continue;
        // The tet in world coordinates, inflated by the distance.
        btConvexHullShape shape(&corners[0].x(), 4);
        shape.setMargin(btScalar(distance));
        btCollisionObject tet;
        tet.setCollisionShape(&shape);
        Touch touch(distance);
        world.contactPairTest(&tet, const_cast<btCollisionObject*>(&anchor), touch);
        if (touch.touched) out.push_back(t);
    }
    return out;
}

LatticeSettings resolveAnchors(const lattice::TetMesh& mesh, const LatticeSettings& settings, const btTransform& pose,
                               btCollisionWorld& world) {
    LatticeSettings out = settings;
    if (settings.anchorRegions.empty() && settings.anchorTo.empty()) return out;
    const std::string& body = settings.name;
    lattice::TetMesh named = mesh;
    named.name = meshNameFor(mesh, settings);
    lattice::validateTetMesh(named); // the regions read centroids, the contact test corners
    if (!finite(pose)) throw InputError("body '" + body + "': pose has a non-finite value");
    settings.check(int(mesh.tets.size()));
    std::vector<int>& fixed = out.fixedTets;
    for (const auto& region : settings.anchorRegions) {
        const std::vector<int> tets = lattice::anchoredTets(mesh, region, body, toEigen(pose));
        fixed.insert(fixed.end(), tets.begin(), tets.end());
    }
    for (size_t i = 0; i < settings.anchorTo.size(); ++i) {
        const btCollisionObject* anchor = settings.anchorTo[i];
        const std::string which = "body '" + body + "': anchor body " + std::to_string(i);
        if (!anchor) throw InputError(which + " is null");
        if (!anchor->isStaticObject()) throw InputError(which + " is not static (only a body that never moves can hold tets fixed)");
        const std::vector<int> tets = tetsTouching(mesh, pose, *anchor, settings.anchorDistance, world);
        if (tets.empty()) {
            std::ostringstream text;
            text << which << " touches no tet (none within " << settings.anchorDistance << " m of it where the body is created)";
            throw InputError(text.str());
        }
        fixed.insert(fixed.end(), tets.begin(), tets.end());
    }
    std::sort(fixed.begin(), fixed.end());
    fixed.erase(std::unique(fixed.begin(), fixed.end()), fixed.end());
    out.anchorRegions.clear();
    out.anchorTo.clear();
    return out;
}

} // namespace shatter
