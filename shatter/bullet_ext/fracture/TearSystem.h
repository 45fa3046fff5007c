#pragma once
// Tearing of soft and plastic visual bodies inside the world step (source 000 §3.6). After the
// deformation step (DeformationSystem), every breakable connection of a body with
// BodySettings::tear enabled (all of them, or those across its tear lines) whose shared
// vertices drifted more than tear.distance apart breaks; the flood fill over shared global ids
// (fracture/Tearing.h) splits the ids along the broken connections and finds the parts; the
// parts are named `<body>.1`, `<body>.2`, ...: a soft body stays as its largest part (in place,
// VisualBody::keepPart) and the others are new bodies that take its collision hulls of their
// primitives (SystemContext::addPart); a plastic body is replaced by one new body
// per part. A body that only
// opened (still one part) stays the body it was: same id, name, shape and joints, with the new
// ids, faces and connections. Every part that touches a joint box of the parent gets a copy of
// the joint (JointTransfer.h).
//
// Soft body: the stretch is measured on the particles' poses after every soft step; each part's
// particles take the parent's particles as they are (pose, velocity, spin, fixed), so mass,
// momentum and angular momentum are handed on exactly. A soft body that only opens is edited
// in place around the broken connections (VisualBody::open, fracture/MeshOpening.h): its ids,
// faces, solver groups and breakable list change there only, its particles and solver state
// not at all, the same as a full recomputation would make them.
//
// Plastic body (ductile fracture, 000 §3.6: "subdivision, deformation and distance breaking"):
// it is rigid between hits, and only a dent moves its primitives apart (each dented primitive
// moves rigidly to its new rest pose, so the vertices it shares with an undented or
// differently dented neighbour part). The stretch is measured on the rest shape after every
// step that dented it (VisualBody::plasticEvents changed), against the breakable connections of
// the mesh as it is then (a subdivision may have cut it finer since). Each part becomes a rigid
// plastic body with the exact mass properties of its primitives, moving as the parent moved at
// the part's centre of mass (geometry::partState), so mass, momentum and angular momentum add
// up to the parent's; a part's primitives fixed by a joint box stay fixed.
#include <shatter/bullet_ext/System.h>
#include <shatter/plugin/fracture/BreakableConnections.h>
#include <shatter/plugin/fracture/Tearing.h>

#include <Eigen/Core>
#include <chrono>
#include <vector>

namespace shatter {

class TearSystem final : public System {
public:
    // Time spent, summed since the last reset (seconds), and what happened.
    struct Timing {
        double stretch = 0.0; // measuring the breakable connections after each soft step
        double tearing = 0.0; // flood fill, ids split, the parts' meshes
        double bodies = 0.0;  // the parts' bodies, particles and joints
        int events = 0, parts = 0, connectionsBroken = 0, jointsRecreated = 0;
    };
    // A tear in double precision, world frame: the parent just before, the parts right after
    // (a soft body's particles; a plastic body's rigid motion with its exact mass properties).
    struct Record {
        int parent = -1; // the parent's body id
        double time = 0.0;
        int connectionsBroken = 0;
        int idsSplit = 0;
        double massBefore = 0.0, massAfter = 0.0;
        Eigen::Vector3d momentumBefore = Eigen::Vector3d::Zero(), momentumAfter = Eigen::Vector3d::Zero();
        Eigen::Vector3d angularMomentumBefore = Eigen::Vector3d::Zero(), angularMomentumAfter = Eigen::Vector3d::Zero();
        std::vector<int> parts; // the parts' body ids
    };

    explicit TearSystem(SystemContext& context) : context_(context) {}
    TearSystem(const TearSystem&) = delete;
    TearSystem& operator=(const TearSystem&) = delete;

    // A soft or plastic body whose settings enable tearing, already in the world: its
    // breakable connections are found now. Throws shatter::InputError naming the body otherwise.
    void add(VisualBody& body);
    // The body's breakable connections as its mesh is now (empty for a body not added).
    std::vector<fracture::BreakableConnection> breakable(const VisualBody& body) const;

    // Tears `body` along `connections` (indices into its physical mesh's connections) now and
    // returns the parts' bodies in part order. A soft body is one of them (its largest part,
    // edited in place); a plastic body is removed unless it stayed one part (then it is the
    // one body returned). Throws shatter::InputError naming the body
    // for a body not added or an index out of range.
    std::vector<VisualBody*> tear(VisualBody& body, const std::vector<int>& connections);

    // System
    bool active() const override { return !bodies_.empty(); }
    void step(double dt, const ContactSnapshot& contacts) override;
    void forget(VisualBody& body) override;

    std::vector<Record> takeRecords();
    const Timing& timing() const { return timing_; }
    void resetTiming() { timing_ = {}; }

private:
    struct Tearable {
        VisualBody* body;
        std::vector<fracture::BreakableConnection> breakable;
        int dentsMeasured = 0; // plastic: VisualBody::plasticEvents() when last measured
    };

    // The indices (into the body's connections) stretched past the distance now; for a plastic
    // body only after a dent since the last call, otherwise none.
    std::vector<int> stretched(Tearable& tearable);
    Tearable& tearable(const VisualBody& body); // a body added
    // The bodies of a torn soft body's parts, in part order: new ones (their meshes moved out
    // of `torn`), holding the parent's particles and its hulls of their primitives
    // (SystemContext::addPart), and the parent itself at `kept` (made that part later,
    // VisualBody::keepPart, which drops the hulls the others took).
    std::vector<VisualBody*> softParts(VisualBody& parent, fracture::TearResult& torn, int kept);
    // The parts of a torn plastic body; `record` has the parent's state before.
    std::vector<VisualBody*> plasticParts(VisualBody& parent, fracture::TearResult& torn, Record& record);
    // Keeps the record and counts the event; `start`: when making its bodies began.
    void finish(Record record, int parts, std::chrono::steady_clock::time_point start);

    SystemContext& context_;
    std::vector<Tearable> bodies_; // in the order they were added
    std::vector<Record> records_;
    Timing timing_;
};

} // namespace shatter
