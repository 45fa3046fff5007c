#include <shatter/bullet_ext/oriented/SoftContacts.h>

#include <shatter/bullet_ext/Convert.h>

#include <cmath>

namespace shatter {

namespace {

struct Collector : btCollisionWorld::ContactResultCallback {
    const btCollisionObject* self = nullptr;
    int primitiveCount = 0;
    std::vector<oriented::ParticleContact> contacts;

    btScalar addSingleResult(btManifoldPoint& point, const btCollisionObjectWrapper* wrap0, int, int index0,
                             const btCollisionObjectWrapper* wrap1, int, int index1) override {
        const bool first = wrap0->getCollisionObject() == self;
        const btCollisionObject* other = first ? wrap1->getCollisionObject() : wrap0->getCollisionObject();
        const int primitive = first ? index0 : index1;
        if (primitive < 0 || primitive >= primitiveCount) return 0;
        const btVector3 normal = first ? point.m_normalWorldOnB : -point.m_normalWorldOnB;
        oriented::ParticleContact c;
        c.particle = primitive;
        c.normal = toEigen(normal).normalized();
        c.distance = double(point.getDistance());
        c.friction = double(self->getFriction() * other->getFriction());
        if (c.normal.allFinite() && std::isfinite(c.distance)) contacts.push_back(c);
        return 0;
    }
};

} // namespace

std::vector<oriented::ParticleContact> softContacts(btCollisionWorld& world, VisualBody& body) {
    Collector collector;
    collector.self = &body.rigidBody();
    collector.primitiveCount = body.shape().primitiveCount();
    world.contactTest(&body.rigidBody(), collector);
    return std::move(collector.contacts);
}

} // namespace shatter
