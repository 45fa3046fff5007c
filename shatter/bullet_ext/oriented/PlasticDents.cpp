#include <shatter/bullet_ext/oriented/PlasticDents.h>

#include <shatter/bullet_ext/Convert.h>

namespace shatter {

std::vector<oriented::Dent> findDents(const ContactSnapshot& contacts, const VisualBody& body, double dt,
                                      std::vector<Eigen::Vector3d>* points) {
    std::vector<oriented::Dent> dents;
    const btCollisionObject* self = &body.rigidBody();
    const double threshold = body.settings().plastic.threshold;
    const btMatrix3x3 worldToMesh = body.meshTransform().getBasis().transpose();
    for (int index : contacts.pairsOf(self)) {
        const ContactPair& pair = contacts.pairs()[index];
        if (pair.gone) continue;
        for (const ContactPoint& point : contacts.points(pair)) {
            if (point.distance > pair.processingThreshold) continue;
            const int primitive = ContactSnapshot::primitiveOn(pair, point, self);
            if (primitive < 0 || primitive >= body.shape().primitiveCount()) continue;
            const double approach = ContactSnapshot::approachSpeed(pair, point);
            if (approach <= threshold) continue;
            const btVector3 push = ContactSnapshot::pushOn(pair, point, self);
            dents.push_back({primitive, toEigen(worldToMesh * push) * (approach * dt)});
            if (points) points->push_back(toEigen(body.meshTransform().invXform(ContactSnapshot::pointOn(pair, point, self))));
        }
    }
    return dents;
}

} // namespace shatter
