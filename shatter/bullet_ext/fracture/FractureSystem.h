#pragma once
// Brittle fracture of visual bodies inside the world step (source 000 §2.3, §3.6). A body with
// BodySettings::fracture enabled breaks where a contact pair gave it more than the threshold
// impulse in one step, or where the application asks (Plugin::fracture). Its fragments
// (physical meshes in the body's rest coordinates) become rigid bodies: a convex hull for a
// single primitive, a group shape otherwise, each with the exact mass properties of its pieces
// and the parent's velocity at its centre of mass (geometry::partState), so mass, momentum and
// angular momentum add up to the parent's. Every fragment that intersects a
// joint box of the parent gets a copy of that joint to the same other body; the old joint goes
// with the parent. Two settings spread the work of a break over frames (both off by default):
// the bodies of a break may ignore each other for a few steps (contactDelaySteps), and a world
// budget of one event per so many steps keeps later hits for later steps (eventSpacingSteps).
#include <shatter/bullet_ext/System.h>
#include <shatter/plugin/fracture/FracturePattern.h>
#include <shatter/plugin/fracture/RemainderEdit.h>
#include <shatter/plugin/geometry/PhysicalMesh.h>
#include <shatter/plugin/geometry/RigidState.h>

#include <BulletCollision/CollisionShapes/btConvexHullShape.h>

#include <cmath>
#include <map>
#include <memory>
#include <vector>

namespace shatter {

class FractureSystem final : public System {
public:
    // Time spent per phase, summed since the last reset (seconds), and what happened.
    struct Timing {
        double impacts = 0.0;   // finding the contact pairs above the threshold
        double placement = 0.0; // the impact in rest coordinates, the pattern's axis, twist and cells placed
        double cutting = 0.0;   // culling and clipping primitives by the cells
        double islands = 0.0;   // connections around the cuts, components, small pieces merged
        double visualMesh = 0.0; // the fragments' primitives, ids, mass and visual meshes with crack faces
        double bodies = 0.0;    // fragment bodies: creation, hulls, velocities, joints
        int events = 0, fragments = 0, jointsRecreated = 0, primitivesCut = 0;
        int subdivisions = 0; // events of bodies in FractureMode::Subdivide (not counted in `events`)
    };
    // A fracture event in double precision, world frame: the parent just before, then each
    // fragment as created (the last 256 are kept until taken).
    struct Record {
        int parent = -1; // the parent's body id
        double time = 0.0;
        geometry::RigidState before;
        std::vector<geometry::RigidState> parts;
        std::vector<VisualBody*> bodies; // the fragments' bodies, valid until they are removed
    };

    explicit FractureSystem(SystemContext& context) : context_(context) {}
    FractureSystem(const FractureSystem&) = delete;
    FractureSystem& operator=(const FractureSystem&) = delete;

    // A body whose settings enable fracture, already in the world: its pattern is built now
    // (throws shatter::InputError naming the body for a bad pattern or pattern file).
    void add(VisualBody& body);
    // Whether the body may break now (a breakable body, depth left, cool-down over).
    bool breakable(const VisualBody& body) const;

    // Breaks `body` at `point` (world), the pattern's axis along `direction` (world, into the
    // body: the way the blow travels), and returns its fragments; none when the body may not
    // break now (see breakable) or the pattern cut nothing off. A body in FractureMode::Subdivide
    // is subdivided in place instead (SubdivisionEvent.h) and none is returned. A body whose
    // visual surface is open stays the rest of itself, edited in place (VisualBody::keepRemainder):
    // it is then the last of the returned bodies; otherwise the rest is a new body and `body` is
    // removed. Same body, settings, point
    // and direction ⇒ same pieces. Throws shatter::InputError naming the body for a
    // non-finite point or a zero or non-finite direction.
    std::vector<VisualBody*> fracture(VisualBody& body, const Eigen::Vector3d& point, const Eigen::Vector3d& direction);

    // Replaces `body` by one body per fragment (physical meshes in the body's rest coordinates,
    // which must partition it): the fracture event without the cutting. A static body's
    // `remainder` fragment (-1: none) stays static; every other fragment moves. Returns the
    // fragments' bodies in the order of `fragments`; `body` is removed from the world.
    std::vector<VisualBody*> replace(VisualBody& body, std::vector<geometry::PhysicalMesh> fragments, int remainder);

    // System
    bool active() const override { return !breakable_.empty() || !apart_.empty(); }
    void step(double dt, const ContactSnapshot& contacts) override;
    void forget(VisualBody& body) override;

    std::vector<Record> takeRecords();
    const Timing& timing() const { return timing_; }
    void resetTiming() { timing_ = {}; }

private:
    struct Breakable {
        VisualBody* body;
        int depthLeft;  // how many more generations may break
        double readyAt; // simulated time the cool-down ends
        std::shared_ptr<const fracture::FracturePattern> pattern; // built once, shared with the fragments
        // Fragments named after it so far: a body that stays the rest of its break names the
        // fragments of its next break on from there ("vase.0".."vase.40", then "vase.41"..).
        int fragmentsNamed = 0;
        // A hit kept for later by the event budget (FractureSettings::eventSpacingSteps): the
        // point and direction in rest coordinates.
        bool waiting = false;
        Eigen::Vector3d waitingPoint = Eigen::Vector3d::Zero(), waitingDirection = Eigen::Vector3d::Zero();
    };
    // The contact pair that struck `body` hardest in this step, if above its threshold.
    struct Impact {
        VisualBody* body;
        Eigen::Vector3d point, direction;
    };
    // fracture(), with the step's contacts when called from step() (a subdivided plastic body
    // dents with them at once).
    std::vector<VisualBody*> breakAt(VisualBody& body, const Eigen::Vector3d& point, const Eigen::Vector3d& direction,
                                     const ContactSnapshot* contacts, double dt);
    bool strongestImpact(const Breakable& b, const ContactSnapshot& contacts, Impact& impact) const;
    // `body`'s entry in breakable_, or end().
    std::vector<Breakable>::iterator entryOf(const VisualBody* body);
    // Whether the world's event budget lets `body` break in this step of length dt: at least
    // its eventSpacingSteps steps since the last event (half a step of slack for rounding).
    bool budgetAllows(const VisualBody& body, double dt) const;

    // The fracture event: fragments become bodies; the rest is either among them
    // (`remainder`) or, with `rest`, the parent itself, edited in place. `hullIsClear`, per
    // fragment or empty, says which may collide as their hull (FractureSettings::hullBelow).
    // The parent takes rest->added's pieces (VisualBody::keepRemainder).
    std::vector<VisualBody*> breakApart(VisualBody& parent, std::vector<geometry::PhysicalMesh> fragments, int remainder,
                                        fracture::RemainderEdit* rest, const std::vector<bool>& hullIsClear);
    // breakApart's steps for the parent that stays as the rest, and for every break.
    void reportRestJoints(const VisualBody& parent);
    void scheduleRest(const VisualBody& parent, int depthLeft, int fragmentsNamed);
    void announce(VisualBody& parent, const std::vector<VisualBody*>& made, const std::vector<VisualBody*>& bodies);
    // Whether every joint of the parent still touches the rest of it after `rest`.
    bool jointsStayWithRemainder(const VisualBody& parent, const fracture::RemainderEdit& rest) const;
    // A body for `mesh` (moved into it, not copied); it collides as a hull when it is one
    // primitive, or when `asHull`.
    VisualBody& makeFragment(const VisualBody& parent, geometry::PhysicalMesh mesh, bool moves, const btTransform& pose,
                             bool asHull);

    // The bodies of one break, which do not collide with each other (Bullet's per-object
    // ignore list, read by the dispatcher's needsCollision) until the end of world step
    // `until` (FractureSettings::contactDelaySteps).
    struct Apart {
        std::vector<VisualBody*> bodies;
        long long until;
    };
    // Keeps the bodies of a break from colliding with each other for `steps` world steps.
    void keepApart(const std::vector<VisualBody*>& bodies, int steps);

    SystemContext& context_;
    std::vector<Breakable> breakable_; // in the order they were added
    std::vector<Apart> apart_;         // in the order of their breaks
    long long steps_ = 0;              // world steps this system has been stepped in
    // The simulated time of the world's last fracture event. Kept as a time, not a step
    // count: the system is not stepped while nothing is breakable, and the budget
    // (FractureSettings::eventSpacingSteps) counts every world step.
    double lastEventTime_ = -INFINITY;
    // The hulls of fragments that collide as one, and those of bodies that left the world since
    // the last step (a body's shape until it is out of the world).
    std::map<const VisualBody*, std::unique_ptr<btConvexHullShape>> hulls_;
    std::vector<std::unique_ptr<btConvexHullShape>> retired_;
    std::vector<Record> records_;
    Timing timing_;
};

} // namespace shatter
