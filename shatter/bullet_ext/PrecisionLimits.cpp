#include <shatter/bullet_ext/PrecisionLimits.h>

#include <BulletCollision/CollisionDispatch/btCollisionObject.h>
#include <BulletCollision/NarrowPhaseCollision/btPersistentManifold.h>
#include <BulletDynamics/Dynamics/btRigidBody.h>

#include <cmath>
#include <cstdio>

namespace shatter {

namespace {

std::string number(double value) {
    char text[32];
    std::snprintf(text, sizeof text, "%.3g", value);
    return text;
}

double massOf(const btCollisionObject& object) {
    const btRigidBody* body = btRigidBody::upcast(&object);
    if (!body || body->getInvMass() == 0) return 0.0;
    return 1.0 / double(body->getInvMass());
}

} // namespace

double heaviestMovableMass() { return std::sqrt(3.0) / double(SIMD_EPSILON); }

std::vector<std::string> precisionWarnings(const std::string& body, double mass, const Eigen::Vector3d& extent) {
    std::vector<std::string> out;
    const std::string who = "body '" + body + "': ";
    if (mass > heaviestMovableMass())
        out.push_back(who + "mass " + number(mass) + " kg is above " + number(heaviestMovableMass()) +
                      " kg, the heaviest Bullet's solver moves at this precision: it will fall through static "
                      "bodies; lower the density, check the mesh units (PhysicalMeshSettings::units, --units) or "
                      "build against Bullet's double-precision libraries");
    const double smallest = extent.minCoeff(), largest = extent.maxCoeff();
    if (smallest < smallestSafeSize)
        out.push_back(who + "its smallest size " + number(smallest) + " m is below " + number(smallestSafeSize) +
                      " m, the size of Bullet's contact margins: contacts will jitter; check the mesh units or "
                      "scale it up (PhysicalMeshSettings::scale, --scale)");
    if (largest > largestSafeSize)
        out.push_back(who + "its largest size " + number(largest) + " m is above " + number(largestSafeSize) +
                      " m: single precision keeps too few digits of its coordinates for stable contacts; check the "
                      "mesh units (PhysicalMeshSettings::units, --units) or split it");
    return out;
}

void MassRatioWatch::check(btDispatcher& dispatcher, const Namer& name, std::vector<std::string>& warnings) {
    for (int i = 0; i < dispatcher.getNumManifolds(); ++i) {
        const btPersistentManifold* m = dispatcher.getManifoldByIndexInternal(i);
        if (m->getNumContacts() == 0) continue;
        const btCollisionObject* a = m->getBody0();
        const btCollisionObject* b = m->getBody1();
        const double ma = massOf(*a), mb = massOf(*b);
        if (ma == 0 || mb == 0 || std::max(ma, mb) <= largestSafeMassRatio * std::min(ma, mb)) continue;
        const auto na = name(*a), nb = name(*b);
        if (!na || !nb || (na->empty() && nb->empty())) continue;
        if (!warned_.insert(std::minmax(a, b)).second) continue;
        const auto label = [](const std::string& n) { return n.empty() ? std::string("an application body") : "body '" + n + "'"; };
        warnings.push_back(label(*na) + " (" + number(ma) + " kg) touches " + label(*nb) + " (" + number(mb) +
                           " kg): a mass ratio above " + number(largestSafeMassRatio) +
                           " makes Bullet's solver converge slowly (the light body sinks or jitters); bring the "
                           "masses closer or raise the world's solver iterations");
    }
}

void MassRatioWatch::forget(const btCollisionObject& object) {
    std::erase_if(warned_, [&](const auto& pair) { return pair.first == &object || pair.second == &object; });
}

} // namespace shatter
