#pragma once
// shatter::Plugin: attaches to an application's btDiscreteDynamicsWorld and runs inside its step.
#include <shatter/bullet_ext/AttachedWorld.h>
#include <shatter/bullet_ext/BodySettings.h>
#include <shatter/bullet_ext/ContactSnapshot.h>
#include <shatter/bullet_ext/Events.h>
#include <shatter/bullet_ext/Joints.h>
#include <shatter/bullet_ext/OrderedContacts.h>
#include <shatter/bullet_ext/PrecisionLimits.h>
#include <shatter/bullet_ext/System.h>
#include <shatter/bullet_ext/VisualBody.h>
#include <shatter/plugin/geometry/PhysicalMesh.h>

#include <BulletCollision/CollisionShapes/btEmptyShape.h>
#include <BulletDynamics/Dynamics/btDiscreteDynamicsWorld.h>
#include <array>
#include <map>
#include <memory>
#include <set>
#include <vector>

namespace shatter {

namespace lattice {
struct TetMesh;
}
class DeformationSystem;
class FractureSystem;
class TearSystem;
class LatticeBody;
class LatticeSystem;
struct LatticeSettings;

// Lifetime. Shatter creates and owns the Bullet objects it puts in the application's world:
// each body's btRigidBody, motion state and collision shape, the joints' constraints, and one
// invisible collision object (an empty shape that collides with nothing) that tells it when
// the world is torn down. The application may clean up the way Bullet's samples do, in any
// order with the plugin:
// - destroy the plugin (or call detach()) first: Shatter takes all of its objects out of the
//   world and deletes them, and restores the dispatcher;
// - or run its own cleanup loop first (remove and delete every constraint; delete each
//   collision object's motion state, remove the object from the world, delete it), then delete
//   the world, and destroy the plugin last (a plugin declared after the world): Shatter notices
//   each of its objects being deleted, forgets it without deleting it again, detaches from the
//   world when its watch object goes, and its destructor touches nothing of the world's.
// Collision shapes stay Shatter's: delete only the shapes the application made.
class Plugin final : private SystemContext { // final: nothing derives from it, so its destructor need not be virtual
public:
    // Registers the group shape's collision algorithms with the world's dispatcher and adds
    // a step hook (a btActionInterface): the application's tick callbacks and world user
    // info are left exactly as they are, and keep being called. For the own contact order
    // (HullPairContacts::contactOrder) it also puts a solver of its own in front of the
    // world's (the application must not replace it while attached: the world then goes back to
    // Bullet's order, with a warning). One Plugin per world (and per dispatcher): a second one
    // throws shatter::InputError, as do the settings' errors; a constructor that throws leaves
    // the world as it was.
    explicit Plugin(btDiscreteDynamicsWorld& world);
    ~Plugin(); // detaches (see Lifetime above)
    Plugin(const Plugin&) = delete;
    Plugin& operator=(const Plugin&) = delete;

    // Removes Shatter's bodies, joints, watch object and step hook from the world, deletes
    // them, restores the dispatcher's own collision algorithms and the world's own solver (if
    // it is still the Plugin's), and ends the Plugin's claim on the world (AttachedWorld.h), so
    // another Plugin may attach. Idempotent.
    void detach();
    // Until detach() or the application's cleanup deleted the watch object.
    bool attached() const { return attached_; }

    // One rigid body with the group shape of `mesh`; `pose` places mesh coordinates in the
    // world. Throws shatter::InputError for a non-finite pose or bad settings. With
    // settings.deformation = Plastic the body dents under hard contacts; with Soft it is an
    // oriented-particle body every step (its solver's gravity is set to the world's).
    VisualBody& addVisualBody(const geometry::PhysicalMesh& mesh, const BodySettings& settings, const btTransform& pose);

    // All bodies of an object (same order as object.bodies) and the Bullet constraints of
    // its joint boxes (see Joint). `perBody` overrides the settings of the bodies it names
    // (e.g. a static door frame).
    struct Object {
        std::vector<VisualBody*> bodies;
        std::vector<Joint*> joints;
    };
    Object addObject(const geometry::PhysicalObject& object, const BodySettings& settings, const btTransform& pose,
                     const std::map<std::string, BodySettings>& perBody = {});

    // Removes the body and its joints from the world (a lattice piece leaves its body).
    void removeBody(VisualBody& body) override;

    // A breakable body from a tet mesh (source 002; see LatticeBody.h): one rigid body until
    // impacts break it, then one per piece. `pose` places mesh coordinates in the world; the
    // settings' anchor regions and bodies are resolved there (resolveAnchors).
    // Throws shatter::InputError naming the body for a bad mesh, bad settings, an anchor that
    // holds no tet or a non-finite pose. Its pieces are VisualBodies, listed in bodies().
    LatticeBody& addLatticeBody(const lattice::TetMesh& mesh, const LatticeSettings& settings, const btTransform& pose);
    // The breakable bodies and their per-step timing (created on first use).
    LatticeSystem& lattices();

    // Breaks a body whose settings enable fracture (BodySettings::fracture) at `point`, the
    // pattern's axis along `direction` (the way the blow travels, into the body): scripted
    // destruction. Returns the fragments (none when the body's depth is used up, it is cooling
    // down, or nothing was cut off); the body is removed. The same call in the same scene
    // gives the same pieces. A body in FractureMode::Subdivide is cut finer there instead and
    // stays (none is returned; event BodySubdivided). Throws shatter::InputError naming the
    // body for a body without fracture, a non-finite point or a zero or non-finite direction.
    std::vector<VisualBody*> fracture(VisualBody& body, const btVector3& point, const btVector3& direction);
    // Visual bodies whose settings enable fracture, their fracture records and timing
    // (created on first use).
    FractureSystem& fractures();
    // Soft visual bodies whose settings enable tearing (BodySettings::tear), their tear records
    // and timing (created on first use).
    TearSystem& tears();

    const std::vector<std::unique_ptr<VisualBody>>& bodies() const { return bodies_; }
    const std::vector<std::unique_ptr<Joint>>& joints() const { return joints_; }
    // The contacts of the last internal step in which a system was active, with the impulses
    // Bullet applied and those the systems applied themselves (soft bodies' pairs).
    const ContactSnapshot& contacts() const { return contacts_; }

    // Events since the last call, oldest first; the queue is emptied.
    std::vector<Event> takeEvents();
    // Warnings since the last call (each names the body, the figure and the remedy): bodies
    // beyond what the world's precision simulates (PrecisionLimits.h), checked when the
    // application adds them, and dynamic pairs in contact with a mass ratio above 1000,
    // checked once a simulated second; and, from the Plugin's making, a world whose contacts
    // stay in Bullet's order although HullPairContacts::contactOrder asked for the own one
    // where possible (contactsOrdered()), or whose application replaced the world's solver
    // while the contacts were in the own order (checked once a step). The queue is emptied.
    std::vector<std::string> takeWarnings();
    // Whether this world's solver and the contact snapshot take the contacts in Shatter's own
    // order (HullPairContacts::contactOrder, OrderedContacts.h), which lets a group pair free its
    // empty leaf manifolds; false: Bullet's order (asked for, or the world's solver does not
    // allow the own one, or the application replaced the Plugin's solver: a warning says why),
    // or detached.
    bool contactsOrdered() const;
    // Simulated time since attach, in seconds (sum of internal steps).
    double time() const override { return time_; }
    btDiscreteDynamicsWorld& world() override { return *world_; }

private:
    class StepHook;
    void onInternalStep(double dt);
    // The systems in the order they run in a step (null: not created yet).
    std::array<System*, 4> stepOrder() const;
    void noteBrokenJoints();
    void removeJoint(size_t index);
    // The application deleted one of Shatter's objects (Watched.h).
    void forgetDeletedBody(VisualBody& body);
    void forgetDeletedJoint(Joint& joint);
    // Drops every reference to a body that leaves the world (systems, joints, contacts, warnings).
    void forgetEverywhere(VisualBody& body);
    // The application deleted the watch object: its world is being torn down. Detaches what
    // can go while the application walks the world's objects (the hook, the dispatcher's
    // algorithms, the joints), not the bodies, which the walk deletes.
    void onWorldTeardown();
    // Whether the body is in a world: a world's destructor clears the broadphase handles of
    // the objects still in it, so a body of a destroyed world has none.
    static bool inWorld(const btCollisionObject& object) { return object.getBroadphaseHandle() != nullptr; }
    // Whether the world can be called: the watch object is still Shatter's and in it.
    bool worldReachable() const;
    void takeOutOfWorld(VisualBody& body);
    void addJointConstraint(Joint& joint, VisualBody& a, VisualBody& b);
    void push(EventType type, int body, int joint, const std::string& name, int count = 0);
    // Warns about a body the application added (pieces Shatter makes are not checked).
    void warnAboutPrecision(const VisualBody& body);
    void watchMassRatios();

    // SystemContext (for the systems only).
    SystemContext& context() { return *this; }
    VisualBody& addBody(geometry::PhysicalMesh mesh, const BodySettings& settings, const btTransform& pose,
                        const std::function<void(VisualBody&, CollisionFilter&)>& prepare = {}) override;
    VisualBody& addPart(VisualBody& parent, geometry::PhysicalMesh part, const std::vector<int>& parents) override;
    // A new body's settings: `settings` with the world's gravity (an error after detach).
    BodySettings settingsInWorld(const BodySettings& settings) const;
    // Puts a new body in the world and the plugin (addBody, addPart).
    VisualBody& enter(std::unique_ptr<VisualBody> body, const std::function<void(VisualBody&, CollisionFilter&)>& prepare);
    void reshape(VisualBody& body, const std::function<void(CollisionFilter&)>& change) override;
    bool removeInWorld(VisualBody& body, const std::function<void()>& removal) override;
    // The body's joints made again where its frame is now (reshape, removeInWorld).
    void rebuildJoints(VisualBody& body);
    void push(EventType type, const VisualBody& body, int count) override;
    void push(Event event) override;
    std::vector<const Joint*> jointsOf(const VisualBody& body) const override;
    Joint& addJoint(const geometry::JointBox& box, VisualBody& a, VisualBody& b) override;
    void removeJoint(const Joint& joint) override;

    btDiscreteDynamicsWorld* world_ = nullptr;
    bool attached_ = false;
    std::unique_ptr<StepHook> hook_;
    // This Plugin's claim on the world's dispatcher, and whether the world's contacts are in the
    // own order (AttachedWorld.h); null once detached.
    std::unique_ptr<AttachedWorld> attachedWorld_;
    // Whether HullPairContacts::contactOrder asks for the own order and the world's solver
    // allows it (a warning if not, an InputError if it was required). Changes nothing else.
    bool ownOrderAllowed(btDiscreteDynamicsWorld& world);
    // The world's solver back in its place, the contacts in Bullet's order.
    void unorderContacts();
    // Bullet's order from now on if the application replaced the world's solver (with a warning).
    void noticeReplacedSolver();
    // In front of the world's solver, taking the contacts in their own order (OrderedContacts.h);
    // null: the world's contacts in Bullet's order.
    std::unique_ptr<OrderedContactSolver> solver_;
    btEmptyShape watchShape_;
    WatchedPtr<btCollisionObject> watch_; // in the world while it is; the application's cleanup deletes it
    std::vector<std::unique_ptr<VisualBody>> bodies_;
    std::vector<std::unique_ptr<Joint>> joints_;
    std::vector<Event> events_;
    std::vector<std::string> warnings_;
    MassRatioWatch massRatios_;
    std::set<const btCollisionObject*> applicationBodies_; // added by the application (not pieces)
    double nextMassRatioCheck_ = 0.0; // simulated time of the next check
    std::unique_ptr<LatticeSystem> lattices_;
    std::unique_ptr<DeformationSystem> deformation_;
    std::unique_ptr<FractureSystem> fractures_;
    std::unique_ptr<TearSystem> tears_;
    ContactSnapshot contacts_;
    double time_ = 0.0;
    int nextBodyId_ = 0;
    int nextJointId_ = 0;
};

} // namespace shatter
