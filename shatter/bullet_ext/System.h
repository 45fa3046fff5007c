#pragma once
// The seam between shatter::Plugin and each module's Bullet-side system (breakable lattice
// bodies, dents and soft bodies, fracture). The Plugin owns the systems and steps them in one
// fixed order inside every internal world step (Plugin.cpp lists it); a system changes the
// world only through the SystemContext it was given, and reads the step's contacts from the
// ContactSnapshot. No system knows the Plugin or another system.
#include <shatter/bullet_ext/ContactSnapshot.h>
#include <shatter/bullet_ext/Events.h>
#include <shatter/bullet_ext/OutOfWorld.h>

#include <BulletDynamics/Dynamics/btDiscreteDynamicsWorld.h>

#include <functional>
#include <vector>

namespace shatter {

class Joint;
class VisualBody;
struct BodySettings;
namespace geometry {
struct JointBox;
struct PhysicalMesh;
}

// What a system may do to the world; implemented by the Plugin.
class SystemContext {
public:
    // The application's world: for Bullet queries (broadphase, gravity) and for changing a
    // body's state (velocities, activation, freezing). Bodies are added and removed below.
    virtual btDiscreteDynamicsWorld& world() = 0;
    // Simulated seconds since the plugin attached.
    virtual double time() const = 0;
    // A new Shatter body in the world (owned by the Plugin; a BodyAdded event is queued), made
    // of `mesh` (moved in when the caller no longer needs it).
    // `prepare`, when given, runs on the body before it enters the world, with the filter it
    // will enter with: a collision shape or filter set there costs nothing, where reshape takes
    // two passes over every pair of the world (Bullet's pair cache), which in a heap of
    // thousands of fragments was most of the frame.
    virtual VisualBody& addBody(geometry::PhysicalMesh mesh, const BodySettings& settings, const btTransform& pose,
                                const std::function<void(VisualBody&, CollisionFilter&)>& prepare = {}) = 0;
    // A new soft body of `part`, a part of a tear of the soft body `parent`, with its
    // particles (parents[i]: the parent's primitive that primitive i is) and the parent's
    // hulls of them (VisualBody's part constructor: the parent must drop those primitives
    // next, e.g. by keepPart), in the world where its primitives are; otherwise as addBody
    // with the parent's settings and the identity pose, then takeParticles.
    virtual VisualBody& addPart(VisualBody& parent, geometry::PhysicalMesh part, const std::vector<int>& parents) = 0;
    // Removes the body and its joints (BodyRemoved event); its pairs in this step's contact
    // snapshot are marked gone. Every system is told (System::forget) first.
    virtual void removeBody(VisualBody& body) = 0;
    // Runs `change` while the body is out of the world (a shape, mass or collision filter that
    // Bullet's cached pairs must not see change in place), then puts it back with the filter
    // `change` leaves (its own unless changed) and rebuilds its joints, whose frames may have
    // moved. Leaving the world drops the body's manifolds, so its pairs in this step's
    // snapshot are marked gone.
    virtual void reshape(VisualBody& body, const std::function<void(CollisionFilter&)>& change) = 0;
    // Runs `removal`, which only removes primitives from the body's group shape
    // (VisualBody::removePrimitives), with the body left in the world: its pairs keep their
    // collision algorithms, leaf pairs and manifolds, which follow the removal and the body's
    // new frame (RemovalInWorld.h), instead of being made anew at the next step. Its pairs in
    // this step's snapshot are marked gone and its joints rebuilt, as by reshape. If the body
    // collides as another shape object after `removal` (its first new frame makes the one that
    // holds the group), or the edit was no pure removal, the body leaves the world and enters
    // it again, as by reshape. Returns whether it stayed in the world.
    virtual bool removeInWorld(VisualBody& body, const std::function<void()>& removal) = 0;
    // Queues an event about `body`; `count` as Event::count says.
    virtual void push(EventType type, const VisualBody& body, int count = 0) = 0;
    // Queues an event as given (its time is set to now).
    virtual void push(Event event) = 0;
    // The joints that hold `body`, in the order they were made.
    virtual std::vector<const Joint*> jointsOf(const VisualBody& body) const = 0;
    // A new joint of `box`'s type and frame (mesh coordinates of both bodies) between a and b,
    // with the bodies' breaking impulse (a JointAdded event is queued).
    virtual const Joint& addJoint(const geometry::JointBox& box, VisualBody& a, VisualBody& b) = 0;
    // Removes the joint, no event (as removeBody removes a body's joints; e.g. a torn body kept
    // in place whose joints went to copies).
    virtual void removeJoint(const Joint& joint) = 0;

protected:
    ~SystemContext() = default;
};

class System {
public:
    virtual ~System() = default;
    // Whether the system has anything to do: the Plugin skips the contact snapshot when no
    // system is active.
    virtual bool active() const = 0;
    // One internal step of `dt` seconds, after Bullet integrated the bodies.
    virtual void step(double dt, const ContactSnapshot& contacts) = 0;
    // Right after step(): a system that solved contacts Bullet only detected (soft bodies)
    // writes the impulses it applied into the snapshot, so that the systems after it and the
    // application (Plugin::contacts) read them as they read Bullet's.
    virtual void recordImpulses(ContactSnapshot&) {}
    // Whether the next step's snapshot must carry the bodies' motion from the end of this
    // step (ContactPair::beforeA/B); recording it costs a pass over the world's bodies.
    virtual bool needsMotionBefore() const { return false; }
    // `body` is about to leave the world (the application or another system removes it):
    // drop every reference to it.
    virtual void forget(VisualBody& body) = 0;
};

} // namespace shatter
