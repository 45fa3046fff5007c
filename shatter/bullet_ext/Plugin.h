#pragma once
// shatter::Plugin: attaches to an application's btDiscreteDynamicsWorld and runs inside its step.
#include <shatter/bullet_ext/BodySettings.h>
#include <shatter/bullet_ext/ContactSnapshot.h>
#include <shatter/bullet_ext/Events.h>
#include <shatter/bullet_ext/Joints.h>
#include <shatter/bullet_ext/System.h>
#include <shatter/bullet_ext/VisualBody.h>
#include <shatter/plugin/geometry/PhysicalMesh.h>

#include <BulletDynamics/Dynamics/btDiscreteDynamicsWorld.h>
#include <array>
#include <map>
#include <memory>
#include <vector>

namespace shatter {

namespace lattice {
struct TetMesh;
}
class DeformationSystem;
class LatticeBody;
class LatticeSystem;
struct LatticeSettings;

class Plugin : private SystemContext {
public:
    // Registers the group shape's collision algorithms with the world's dispatcher and adds
    // a step hook (a btActionInterface): the application's tick callbacks and world user
    // info are left exactly as they are, and keep being called.
    explicit Plugin(btDiscreteDynamicsWorld& world);
    ~Plugin(); // detaches
    Plugin(const Plugin&) = delete;
    Plugin& operator=(const Plugin&) = delete;

    // Removes Shatter's bodies, joints and step hook from the world and restores the
    // dispatcher's own collision algorithms. Idempotent.
    void detach();
    bool attached() const { return world_ != nullptr; }

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
    // impacts break it, then one per piece. `pose` places mesh coordinates in the world.
    // Throws shatter::InputError naming the body for a bad mesh, bad settings or a
    // non-finite pose. Its pieces are VisualBodies, listed in bodies().
    LatticeBody& addLatticeBody(const lattice::TetMesh& mesh, const LatticeSettings& settings, const btTransform& pose);
    // The breakable bodies and their per-step timing (created on first use).
    LatticeSystem& lattices();

    const std::vector<std::unique_ptr<VisualBody>>& bodies() const { return bodies_; }
    const std::vector<std::unique_ptr<Joint>>& joints() const { return joints_; }

    // Events since the last call, oldest first; the queue is emptied.
    std::vector<Event> takeEvents();
    // Simulated time since attach, in seconds (sum of internal steps).
    double time() const override { return time_; }
    btDiscreteDynamicsWorld& world() override { return *world_; }

private:
    class StepHook;
    void onInternalStep(double dt);
    // The systems in the order they run in a step (null: not created yet).
    std::array<System*, 2> stepOrder() const;
    void noteBrokenJoints();
    void removeJoint(size_t index);
    void addJointConstraint(Joint& joint, VisualBody& a, VisualBody& b);
    void push(EventType type, int body, int joint, const std::string& name, int count = 0);

    // SystemContext (for the systems only).
    SystemContext& context() { return *this; }
    VisualBody& addBody(const geometry::PhysicalMesh& mesh, const BodySettings& settings,
                        const btTransform& pose) override;
    void reshape(VisualBody& body, const std::function<void(CollisionFilter&)>& change) override;
    void push(EventType type, const VisualBody& body, int count) override;

    btDiscreteDynamicsWorld* world_ = nullptr;
    std::unique_ptr<StepHook> hook_;
    std::vector<std::unique_ptr<VisualBody>> bodies_;
    std::vector<std::unique_ptr<Joint>> joints_;
    std::vector<Event> events_;
    std::unique_ptr<LatticeSystem> lattices_;
    std::unique_ptr<DeformationSystem> deformation_;
    ContactSnapshot contacts_;
    double time_ = 0.0;
    int nextBodyId_ = 0;
    int nextJointId_ = 0;
};

} // namespace shatter
