#include <shatter/bullet_ext/lattice/ImpulseTakeBack.h>

namespace shatter {

void ImpulseTakeBack::takeBack(const ContactPair& pair, const ContactPoint& p) {
    for (btRigidBody* body : {pair.rigidA, pair.rigidB})
        if (body && body->getInvMass() > 0) held_.insert(body);
    ContactSnapshot::undoImpulse(pair, p);
}

void ImpulseTakeBack::finish(double dt) {
    for (btRigidBody* body : held_) body->setLinearVelocity(body->getLinearVelocity() - body->getGravity() * btScalar(dt));
    held_.clear();
}

} // namespace shatter
