#pragma once
// The contacts of a soft body in one world step, as the oriented-particle solver takes them
// (source 000 §3.2: collisions go through the world's own detection). Bullet detects the soft
// body's contacts but does not solve them (its rigid body is kinematic with no contact
// response); they are read from the step's ContactSnapshot, and the soft step solves them
// with the particles, moving the dynamic Bullet bodies they touch by their share: momentum
// goes both ways.
#include <shatter/bullet_ext/ContactSnapshot.h>
#include <shatter/bullet_ext/VisualBody.h>
#include <shatter/plugin/oriented/SelfContacts.h>

#include <span>
#include <utility>
#include <vector>

namespace shatter {

class SoftContacts {
public:
    // Gathers `body`'s contacts from the snapshot: one per contact point, on the particle of
    // the touched primitive, the normal pointing into the soft side, Bullet's friction
    // product. A dynamic Bullet body becomes a coupled contact body; everything else (static,
    // kinematic, another soft body) is a surface that moves as Bullet moved it in the step; with
    // another soft body, which solves the same points, each side takes half the distance.
    // With the body's solver setting selfContact, adds the contacts between its unconnected
    // primitives, from the body's own candidate list `selfContact` (kept between steps).
    // Throws shatter::InputError naming the body for a non-finite contact.
    void gather(const ContactSnapshot& snapshot, const VisualBody& body, double dt,
                oriented::SelfContactCandidates& selfContact);

    const std::vector<oriented::ParticleContact>& contacts() const { return contacts_; }
    std::vector<oriented::ContactBody>& bodies() { return bodies_; }

    // Moves each coupled Bullet body by the correction the soft step gave it and adds the
    // matching velocity (shift/dt, turn/dt); wakes it when that exceeds its sleeping speed.
    void applyToBodies(double dt) const;

    // The impulses the soft step applied at the snapshot's points (`onParticles`, one per
    // contact, OrientedSolver::contactImpulses), appended to `out` as (point index, impulse on
    // the pair's body A): Bullet solved none of these pairs, so this is their whole impulse.
    // When both bodies of a pair are soft, each solved the point on its own and gives half.
    void impulsesOnA(std::span<const Eigen::Vector3d> onParticles, std::vector<std::pair<int, btVector3>>& out) const;

private:
    int bodyIndex(btRigidBody& rigid);

    std::vector<oriented::ParticleContact> contacts_;
    // Per contact from the snapshot: its point's index in the snapshot, and the share of the
    // impulse on the particle that is the impulse on the pair's body A (±1, ±½). Self-contacts
    // (after these) have no point.
    std::vector<std::pair<int, btScalar>> points_;
    std::vector<oriented::ContactBody> bodies_;
    std::vector<btRigidBody*> rigid_; // bodies_[k]'s Bullet body
};

// Removes the points of every manifold that involves one of `objects`: a soft body's points
// were recorded on primitives that have moved since, and Bullet would refresh them from
// those stale places. Bullet does not solve these pairs, so nothing is lost.
void clearManifolds(btDispatcher& dispatcher, const std::vector<const btCollisionObject*>& objects);

} // namespace shatter
