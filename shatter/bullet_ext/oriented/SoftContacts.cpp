#include <shatter/bullet_ext/oriented/SoftContacts.h>

#include <shatter/bullet_ext/Convert.h>
#include <shatter/plugin/common/InputError.h>

#include <BulletCollision/NarrowPhaseCollision/btPersistentManifold.h>
#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace shatter {

namespace {

bool coupled(const btRigidBody* rigid) { return rigid && rigid->getInvMass() > 0 && !rigid->isStaticOrKinematicObject(); }

Eigen::Vector3d velocityAt(const btRigidBody& body, const btVector3& point) {
    return toEigen(body.getVelocityInLocalPoint(point - body.getCenterOfMassPosition()));
}

} // namespace

int SoftContacts::bodyIndex(btRigidBody& rigid) {
    const auto it = std::find(rigid_.begin(), rigid_.end(), &rigid);
    if (it != rigid_.end()) return int(it - rigid_.begin());
    oriented::ContactBody b;
    b.inverseMass = double(rigid.getInvMass());
    b.inverseInertia = toEigen(rigid.getInvInertiaTensorWorld());
    b.centre = toEigen(rigid.getCenterOfMassPosition());
    bodies_.push_back(b);
    rigid_.push_back(&rigid);
    return int(rigid_.size()) - 1;
}

void SoftContacts::gather(const ContactSnapshot& snapshot, const VisualBody& body, double dt,
                          oriented::SelfContactCandidates& selfContact) {
    contacts_.clear();
    points_.clear();
    bodies_.clear();
    rigid_.clear();
    const btCollisionObject* self = &body.rigidBody();
    const int primitives = body.shape().primitiveCount();
    for (int index : snapshot.pairsOf(self)) {
        const ContactPair& pair = snapshot.pairs()[index];
        if (pair.gone) continue;
        const btCollisionObject* other = pair.other(self);
        btRigidBody* rigid = pair.rigid(other);
        const int coupledBody = coupled(rigid) ? bodyIndex(*rigid) : -1;
        const double friction = double(self->getFriction() * other->getFriction());
        // Another soft body has no contact response (Bullet solves neither of them) and solves
        // this pair's points too, with this one as its surface.
        const bool otherSoft = !other->hasContactResponse();
        // Each takes half the overlap (or gap), or together they would push out twice and rattle.
        const double distanceShare = otherSoft ? 0.5 : 1.0;
        // The soft body's impulse is the pair's impulse on A with this sign; another soft body
        // records the other half.
        const btScalar share = btScalar(pair.a == self ? 1.0 : -1.0) * btScalar(otherSoft ? 0.5 : 1.0);
        const std::span<const ContactPoint> points = snapshot.points(pair);
        for (size_t k = 0; k < points.size(); ++k) {
            const ContactPoint& point = points[k];
            const int primitive = ContactSnapshot::primitiveOn(pair, point, self);
            if (primitive < 0 || primitive >= primitives) continue;
            oriented::ParticleContact c;
            c.particle = primitive;
            c.normal = toEigen(ContactSnapshot::pushOn(pair, point, self)).normalized();
            c.distance = distanceShare * double(point.distance);
            c.friction = friction;
            c.body = coupledBody;
            const btVector3& onOther = ContactSnapshot::pointOn(pair, point, other);
            c.point = toEigen(onOther);
            // Bullet has integrated the other body over this step already: its surface moved
            // by its velocity times the step (a static body's is zero).
            if (rigid) c.surfaceMove = velocityAt(*rigid, onOther) * dt;
            if (!(c.normal.allFinite() && std::isfinite(c.distance) && c.point.allFinite() && c.surfaceMove.allFinite())) {
                std::ostringstream msg;
                msg << "body '" << body.name() << "': a contact of primitive " << primitive
                    << " has a non-finite normal, distance or point";
                throw InputError(msg.str());
            }
            contacts_.push_back(c);
            points_.emplace_back(pair.firstPoint + int(k), share);
        }
    }
    const oriented::OrientedSolver& solver = *body.solver();
    if (solver.settings().selfContact) {
        const double friction = double(self->getFriction() * self->getFriction());
        // Pairs whose own boxes overlap (the contact tree's 1 cm growth doubled the
        // candidates, all neighbours), with speculative contacts up to 1 cm apart.
        selfContact.addContacts(body.shape().primitives(), body.shape().tree(), solver.groups(),
                                body.shape().contactSlack(), friction, contacts_);
    }
}

void SoftContacts::applyToBodies(double dt) const {
    for (size_t k = 0; k < rigid_.size(); ++k) {
        const oriented::ContactBody& b = bodies_[k];
        if (b.shift.isZero(0.0) && b.turn.isZero(0.0)) continue;
        btRigidBody& rigid = *rigid_[k];
        btTransform pose = rigid.getCenterOfMassTransform();
        pose.setOrigin(pose.getOrigin() + toBullet(b.shift));
        const double angle = b.turn.norm();
        if (angle > 0.0) {
            const btQuaternion turn(toBullet(Eigen::Vector3d(b.turn / angle)), btScalar(angle));
            pose.setRotation((turn * pose.getRotation()).normalized());
        }
        const btVector3 dv = toBullet(Eigen::Vector3d(b.shift / dt)), dw = toBullet(Eigen::Vector3d(b.turn / dt));
        rigid.setCenterOfMassTransform(pose);
        rigid.setLinearVelocity(rigid.getLinearVelocity() + dv);
        rigid.setAngularVelocity(rigid.getAngularVelocity() + dw);
        if (dv.length() > rigid.getLinearSleepingThreshold() || dw.length() > rigid.getAngularSleepingThreshold())
            rigid.activate();
    }
}

void SoftContacts::impulsesOnA(std::span<const Eigen::Vector3d> onParticles,
                               std::vector<std::pair<int, btVector3>>& out) const {
    if (onParticles.size() < points_.size())
        throw std::invalid_argument("SoftContacts::impulsesOnA: fewer impulses than the gathered contacts");
    for (size_t k = 0; k < points_.size(); ++k)
        out.emplace_back(points_[k].first, points_[k].second * toBullet(onParticles[k]));
}

void clearManifolds(btDispatcher& dispatcher, const std::vector<const btCollisionObject*>& objects) {
    const int count = dispatcher.getNumManifolds();
    for (int m = 0; m < count; ++m) {
        btPersistentManifold* manifold = dispatcher.getManifoldByIndexInternal(m);
        if (manifold->getNumContacts() == 0) continue;
        const auto involved = [&](const btCollisionObject* o) {
            return std::find(objects.begin(), objects.end(), o) != objects.end();
        };
        if (involved(manifold->getBody0()) || involved(manifold->getBody1())) manifold->clearManifold();
    }
}

} // namespace shatter
