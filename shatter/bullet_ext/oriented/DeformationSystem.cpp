#include <shatter/bullet_ext/oriented/DeformationSystem.h>

#include <shatter/bullet_ext/VisualBody.h>
#include <shatter/bullet_ext/oriented/PlasticDents.h>
#include <shatter/bullet_ext/oriented/SoftContacts.h>

#include <LinearMath/btAabbUtil2.h>
#include <algorithm>
#include <cmath>

namespace shatter {

void DeformationSystem::add(VisualBody& body) {
    bodies_.push_back(&body);
    if (body.deformation() == Deformation::Plastic) ++plastic_;
    if (body.deformation() != Deformation::Soft) return;
    softObjects_.push_back(&body.rigidBody());
    // A skin of the contact slack: a list then lasts while no primitive has moved 1 cm, and
    // second neighbours of a sheet of 3 cm quads stay off it.
    selfContact_.emplace(&body, oriented::SelfContactCandidates(body.shape().contactSlack()));
    // Bullet files a kinematic body under static ones and pairs it with none of them; a soft
    // body must meet the ground and every other static body in the broadphase.
    context_.reshape(body, [](CollisionFilter& filter) {
        filter.group = int(btBroadphaseProxy::DefaultFilter);
        filter.mask = int(btBroadphaseProxy::AllFilter);
    });
}

void DeformationSystem::forget(VisualBody& body) {
    const auto it = std::find(bodies_.begin(), bodies_.end(), &body);
    if (it == bodies_.end()) return;
    if (body.deformation() == Deformation::Plastic) --plastic_;
    std::erase(softObjects_, &body.rigidBody());
    selfContact_.erase(&body);
    asleep_.erase(&body);
    pending_.erase(&body);
    bodies_.erase(it);
}

void DeformationSystem::step(double dt, const ContactSnapshot& contacts) {
    softImpulses_.clear();
    for (VisualBody* body : bodies_) {
        if (body->deformation() == Deformation::Soft) {
            stepSoft(*body, dt, contacts);
            continue;
        }
        const auto dents = findDents(contacts, *body, dt);
        if (dents.empty()) continue;
        oriented::PlasticResult result;
        context_.reshape(*body, [&](CollisionFilter&) { result = body->dent(dents); });
        if (!result.moved.empty()) context_.push(EventType::BodyDented, *body, int(result.moved.size()));
    }
    if (!softObjects_.empty()) clearManifolds(*context_.world().getDispatcher(), softObjects_);
}

bool DeformationSystem::readyToSleep(const VisualBody& body) const {
    const oriented::OrientedSolver& solver = *body.solver();
    return solver.settings().sleepSpeed > 0.0 &&
           (asleep_.contains(&body) || solver.quietTime() >= solver.settings().sleepTime);
}

bool DeformationSystem::touchedByMovingBody(const ContactSnapshot& contacts, const VisualBody& body) const {
    const btCollisionObject* self = &body.rigidBody();
    for (int index : contacts.pairsOf(self)) {
        const ContactPair& pair = contacts.pairs()[index];
        const btCollisionObject* other = pair.other(self);
        if (pair.gone || !other->isActive()) continue;
        // Another soft body is kept active while awake: it moves unless it is as quiet as this
        // one would need to be (so soft bodies resting on each other fall asleep together).
        const auto soft = std::find_if(bodies_.begin(), bodies_.end(), [&](const VisualBody* b) {
            return b->deformation() == Deformation::Soft && &b->rigidBody() == other;
        });
        if (soft == bodies_.end() || !readyToSleep(**soft)) return true;
    }
    return false;
}

void DeformationSystem::stepSoft(VisualBody& body, double dt, const ContactSnapshot& contacts) {
    btRigidBody& rigid = body.rigidBody();
    const bool asleep = asleep_.contains(&body);
    // Only a body that may sleep asks (the default, sleepSpeed 0, never does): a search of the
    // soft bodies per touching pair, every substep.
    const bool moved = (asleep || body.solver()->settings().sleepSpeed > 0.0) && touchedByMovingBody(contacts, body);
    if (asleep) {
        // Anyone may wake it: a moving body touching it, or forceActivationState on its rigid body.
        if (!moved && rigid.getActivationState() == ISLAND_SLEEPING) return;
        asleep_.erase(&body);
        rigid.forceActivationState(DISABLE_DEACTIVATION); // what VisualBody gives a soft body
    }
    oriented::OrientedSolver& solver = *body.solver();
    double stepTime = dt;
    int substeps = 1;
    if (solver.settings().substepsPerStep > 1 && !dueForStep(body, dt, stepTime, substeps)) return;
    softContacts_.gather(contacts, body, stepTime, selfContact_.at(&body));
    // The solver takes the gathered world substeps one by one with these contacts, each as
    // stiff as at substepsPerStep 1, when all it touches stands still (static bodies, its own
    // primitives); a body or a moving surface met late (asleep, or first seen in a skipped
    // substep) makes it one step over the whole time, its corrections shared with the body.
    const auto& found = softContacts_.contacts();
    if (std::any_of(found.begin(), found.end(), [](const oriented::ParticleContact& c) {
            return c.body >= 0 || !c.surfaceMove.isZero(0.0);
        }))
        substeps = 1;
    body.advanceSoft(stepTime / substeps, found, softContacts_.bodies(), substeps);
    softContacts_.impulsesOnA(solver.contactImpulses(), softImpulses_);
    softContacts_.applyToBodies(stepTime);
    context_.world().updateSingleAabb(&rigid);
    if (!moved && readyToSleep(body)) {
        // Bullet then skips its pairs with static bodies (both asleep), the bulk of its contacts.
        solver.stop();
        rigid.forceActivationState(ISLAND_SLEEPING);
        asleep_.insert(&body);
        pending_.erase(&body);
    }
}

bool DeformationSystem::movingBodyNear(const VisualBody& body, double time) const {
    const btRigidBody& self = body.rigidBody();
    const btScalar slack = btScalar(body.shape().contactSlack());
    const btVector3 lo = self.getBroadphaseHandle()->m_aabbMin - btVector3(slack, slack, slack);
    const btVector3 hi = self.getBroadphaseHandle()->m_aabbMax + btVector3(slack, slack, slack);
    const btCollisionObjectArray& objects = context_.world().getCollisionObjectArray();
    for (int i = 0; i < objects.size(); ++i) {
        const btCollisionObject* other = objects[i];
        if (other == &self || other->isStaticObject() || !(other->isActive() || other->isKinematicObject()) ||
            !other->getBroadphaseHandle())
            continue;
        btVector3 otherLo = other->getBroadphaseHandle()->m_aabbMin, otherHi = other->getBroadphaseHandle()->m_aabbMax;
        if (const btRigidBody* rigid = btRigidBody::upcast(other)) {
            const btVector3 sweep = rigid->getLinearVelocity() * btScalar(time);
            otherLo.setMin(otherLo + sweep);
            otherHi.setMax(otherHi + sweep);
        }
        if (TestAabbAgainstAabb2(lo, hi, otherLo, otherHi)) return true;
    }
    return false;
}

namespace {
// The width of the body's thinnest primitive at rest: over each primitive's face normals, the
// least extent of its vertices along one.
double thinnestWidth(const VisualBody& body) {
    double thinnest = INFINITY;
    for (const geometry::ConvexPolyhedron& primitive : body.physicalMesh().primitives)
        for (const geometry::Plane& plane : primitive.planes()) {
            double lo = INFINITY, hi = -INFINITY;
            for (const Eigen::Vector3d& x : primitive.vertices()) {
                lo = std::min(lo, plane.normal.dot(x));
                hi = std::max(hi, plane.normal.dot(x));
            }
            thinnest = std::min(thinnest, hi - lo);
        }
    return thinnest;
}

// The largest distance of a primitive's vertex from the primitive's centre of mass, over the
// body at rest: the lever arm of a particle's spin.
double farthestCorner(const VisualBody& body) {
    double farthest = 0.0;
    for (const geometry::ConvexPolyhedron& primitive : body.physicalMesh().primitives) {
        const Eigen::Vector3d centre = primitive.massProperties(1.0).centerOfMass;
        for (const Eigen::Vector3d& x : primitive.vertices()) farthest = std::max(farthest, (x - centre).norm());
    }
    return farthest;
}
} // namespace

int DeformationSystem::substepsWithinReach(const VisualBody& body, double dt, int most, Pending& pending) const {
    if (pending.halfThinnest < 0.0) {
        pending.halfThinnest = 0.5 * thinnestWidth(body);
        pending.farthestCorner = farthestCorner(body);
    }
    // A spinning primitive's corners move by its spin times their distance from its centre,
    // on top of its centre's motion (a tumbling piece could turn a corner through a thin wall).
    const oriented::OrientedParticles& particles = body.solver()->particles();
    double fastest = 0.0;
    for (int i = 0; i < particles.size(); ++i)
        fastest = std::max(fastest, particles.velocity[i].norm() + particles.angularVelocity[i].norm() * pending.farthestCorner);
    const double reach = std::max(body.shape().contactSlack(), pending.halfThinnest);
    const double travel = fastest * dt; // per substep
    if (travel * most <= reach) return most;
    return std::max(1, int(reach / travel));
}

bool DeformationSystem::dueForStep(VisualBody& body, double dt, double& stepTime, int& substeps) {
    btRigidBody& rigid = body.rigidBody();
    Pending& pending = pending_[&body];
    pending.time += dt;
    ++pending.substeps;
    // A moving body's box is from before this substep's motion, and one coming near is first
    // met by the next substep's narrowphase, whose contacts the body then steps with: so its
    // box is swept over three substeps. Near a moving body the body steps every substep, as
    // with substepsPerStep 1 (a touch is at most one substep late). Moving fast on its own, it
    // steps as often as its reach needs (every substep for a thrown jelly, every second one for
    // a sheet's swinging edge at 1 m/s).
    const int every = substepsWithinReach(body, dt, body.solver()->settings().substepsPerStep, pending);
    const bool near = movingBodyNear(body, 3.0 * dt);
    // Asleep to Bullet in this substep's narrowphase, it has no contacts with static bodies
    // now: it steps in the next substep, whose narrowphase sees them.
    const bool sawStaticPairs = rigid.getActivationState() != ISLAND_SLEEPING;
    const bool due = sawStaticPairs && (near || pending.substeps >= every);
    if (due) {
        stepTime = pending.time;
        substeps = pending.substeps;
        pending.time = 0.0;
        pending.substeps = 0;
    }
    // Bullet pairs it with static bodies in the next substep only if it may step then.
    const bool nextDue = near || pending.substeps + 1 >= every;
    rigid.forceActivationState(nextDue ? DISABLE_DEACTIVATION : ISLAND_SLEEPING);
    return due;
}

void DeformationSystem::recordImpulses(ContactSnapshot& contacts) {
    for (const auto& [point, impulse] : softImpulses_) contacts.addImpulse(point, impulse);
}

} // namespace shatter
