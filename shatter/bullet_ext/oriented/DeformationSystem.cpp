#include <shatter/bullet_ext/oriented/DeformationSystem.h>

#include <shatter/bullet_ext/VisualBody.h>
#include <shatter/bullet_ext/oriented/PlasticDents.h>
#include <shatter/bullet_ext/oriented/SoftContacts.h>

#include <algorithm>

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
    softContacts_.gather(contacts, body, dt, selfContact_.at(&body));
    body.advanceSoft(dt, softContacts_.contacts(), softContacts_.bodies());
    softContacts_.impulsesOnA(solver.contactImpulses(), softImpulses_);
    softContacts_.applyToBodies(dt);
    context_.world().updateSingleAabb(&rigid);
    if (!moved && readyToSleep(body)) {
        // Bullet then skips its pairs with static bodies (both asleep), the bulk of its contacts.
        solver.stop();
        rigid.forceActivationState(ISLAND_SLEEPING);
        asleep_.insert(&body);
    }
}

void DeformationSystem::recordImpulses(ContactSnapshot& contacts) {
    for (const auto& [point, impulse] : softImpulses_) contacts.addImpulse(point, impulse);
}

} // namespace shatter
