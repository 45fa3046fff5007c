#pragma once
// Runs the deformable visual bodies inside the world step (source 000 §3.2-3.5): a plastic
// body dents where a contact approached it faster than its threshold (PlasticDents.h) and
// stays one rigid body; a soft body takes one oriented-particle step with its contacts
// (SoftContacts.h), moving the dynamic bodies it touches by their share, and its shape is
// refitted to the particles in place (with SolverSettings::substepsPerStep n > 1, one step of
// n substeps while no moving body is near). A soft body with a sleep speed (SolverSettings) that
// has been quiet for its sleep time, touching nothing that moves, sleeps: it is not stepped,
// and Bullet (its rigid body marked sleeping) pairs it only with moving bodies, the first of
// which to touch it wakes it.
#include <shatter/bullet_ext/System.h>
#include <shatter/bullet_ext/oriented/SoftContacts.h>

#include <unordered_map>
#include <unordered_set>
#include <vector>

namespace shatter {

class VisualBody;

class DeformationSystem final : public System {
public:
    explicit DeformationSystem(SystemContext& context) : context_(context) {}

    // A body with BodySettings::deformation Plastic or Soft, already in the world.
    void add(VisualBody& body);

    bool active() const override { return !bodies_.empty(); }
    void step(double dt, const ContactSnapshot& contacts) override;
    // The soft bodies' contact impulses of this step (Bullet does not solve their pairs).
    void recordImpulses(ContactSnapshot& contacts) override;
    // Plastic bodies read the approach speed of a contact from the bodies' motion before the step.
    bool needsMotionBefore() const override { return plastic_ > 0; }
    void forget(VisualBody& body) override;

private:
    SystemContext& context_;
    std::vector<VisualBody*> bodies_; // in the order they were added
    int plastic_ = 0;                 // how many of them are plastic
    std::vector<const btCollisionObject*> softObjects_; // the soft ones' rigid bodies
    SoftContacts softContacts_;       // one soft body's at a time; kept to reuse its storage
    std::vector<std::pair<int, btVector3>> softImpulses_; // (snapshot point, impulse on A) of this step
    std::unordered_map<const VisualBody*, oriented::SelfContactCandidates> selfContact_; // per soft body
    std::unordered_set<const VisualBody*> asleep_; // soft bodies not stepped (stepSoft)
    // Soft bodies with SolverSettings::substepsPerStep > 1: the time and substeps since their
    // last step.
    struct Pending {
        double time = 0.0;
        int substeps = 0;
        double halfThinnest = -1.0; // substepsWithinReach's length, found once (m)
        double farthestCorner = -1.0; // and its lever arm for spin: a primitive vertex's largest distance from its centre (m)
    };
    std::unordered_map<const VisualBody*, Pending> pending_;

    // Whether soft `body` has a sleep speed and is asleep or has been quiet for its sleep time.
    bool readyToSleep(const VisualBody& body) const;
    // Whether a body Bullet keeps active (a moving one: static bodies are kept asleep), other
    // than a soft body ready to sleep, has a contact with soft `body` in the snapshot.
    bool touchedByMovingBody(const ContactSnapshot& contacts, const VisualBody& body) const;
    // Whether a moving body (not static, and awake or kinematic: soft bodies are) other than
    // soft `body` may reach its box within `time` seconds: its box swept by its velocity over
    // that time overlaps the soft body's box grown by its contact slack.
    bool movingBodyNear(const VisualBody& body, double time) const;
    // How many substeps of dt (at least 1, at most `most`) soft `body`'s fastest point (a
    // particle's speed plus its spin times the farthest corner of any primitive) takes to move
    // its reach: its contact slack or half its thinnest primitive (its width,
    // kept in `pending`). Its contacts are queried at least that often: stepping longer on one
    // query could pass a thin static wall by (a thrown jelly). (A primitive that moves less
    // than its own width between two contact queries overlaps any wall it crosses at one of
    // them, however thin the wall; half leaves room for its turning. The slack is the lower
    // limit for thin primitives.)
    int substepsWithinReach(const VisualBody& body, double dt, int most, Pending& pending) const;
    // Steps soft `body`, or leaves it asleep; puts it to sleep when it has been quiet long enough.
    void stepSoft(VisualBody& body, double dt, const ContactSnapshot& contacts);
    // A body with substepsPerStep > 1: whether it steps in this substep, and over what time in
    // how many world substeps; between its steps Bullet sees it asleep (no pairs with static bodies).
    bool dueForStep(VisualBody& body, double dt, double& stepTime, int& substeps);
};

} // namespace shatter
