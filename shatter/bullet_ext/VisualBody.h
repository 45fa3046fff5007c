#pragma once
// A Shatter body in a Bullet world: one btRigidBody with a GroupShape, and the visual mesh
// that follows its primitives. A deformable body (BodySettings::deformation) also carries the
// oriented-particle solver of its primitives (source 000 §3.2-3.5).
#include <shatter/bullet_ext/BodySettings.h>
#include <shatter/bullet_ext/Watched.h>
#include <shatter/bullet_ext/shape/FramedShape.h>
#include <shatter/bullet_ext/shape/GroupShape.h>
#include <shatter/plugin/fracture/MeshOpening.h>
#include <shatter/plugin/fracture/PrimitiveIndex.h>
#include <shatter/plugin/fracture/RemainderEdit.h>
#include <shatter/plugin/fracture/SurfaceIndex.h>
#include <shatter/plugin/fracture/Tearing.h>
#include <shatter/plugin/geometry/PhysicalMesh.h>
#include <shatter/plugin/oriented/OrientedSolver.h>
#include <shatter/plugin/oriented/PlasticDeformation.h>
#include <shatter/plugin/oriented/PrimitiveDeformation.h>

#include <BulletDynamics/Dynamics/btRigidBody.h>
#include <LinearMath/btDefaultMotionState.h>
#include <functional>
#include <memory>
#include <optional>
#include <span>

namespace shatter {

class VisualBody {
public:
    VisualBody(int id, geometry::PhysicalMesh mesh, const BodySettings& settings, const btTransform& meshPose);
    // Soft body: `part`, a part of a tear of the soft body `parent` (fracture::tearMesh), where
    // parents[i] (strictly increasing) is the parent's primitive that the part's primitive i
    // is. The body a new body
    // of `part` is once its particles took the parent's (takeParticles), bit for bit, but the
    // group shape takes the parent's hulls of those primitives instead of building them
    // (GroupShape's taking constructor: the parent's shape must then drop them, e.g. by
    // keepPart, before anything else reads it). The parent's shape must be where its
    // particles were last fitted (as keepPart). The shape's box is the part's rest box (where
    // a new body of it enters the world) until fitShapeBox(). Throws shatter::InputError
    // naming the body for a body that is not soft or parents that do not match.
    VisualBody(int id, VisualBody& parent, geometry::PhysicalMesh part, const std::vector<int>& parents,
               const BodySettings& settings);
    VisualBody(const VisualBody&) = delete;
    VisualBody& operator=(const VisualBody&) = delete;

    // Called when someone else deletes the rigid body (an application's cleanup loop, as in
    // Bullet's samples): the owner must then drop this VisualBody without touching the world.
    void onRigidBodyDeleted(std::function<void(VisualBody&)> deleted) { rigidBodyDeleted_ = std::move(deleted); }

    int id() const { return id_; }
    const std::string& name() const { return mesh_.name; }
    btRigidBody& rigidBody() { return *rigid_; }
    const btRigidBody& rigidBody() const { return *rigid_; }
    // The group shape; its primitives are in the body frame until a dent moves the body
    // frame (then the rigid body's collision shape is a compound holding it, see below).
    // A rigid or plastic body builds it at the first call (or edit, or readyToEnter), so a
    // body that collides as another shape (collideAs) never pays for it unless asked. Building
    // is not thread-safe: call it from the thread that steps the world.
    const GroupShape& shape() const { return group(); }
    // The group shape's primitives (shape frame), without building it. Read them at once:
    // building the shape moves them into it, and the vector returned before is then empty.
    const std::vector<geometry::ConvexPolyhedron>& shapePrimitives() const {
        return shape_ ? shape_->primitives() : unbuilt_;
    }
    // Before the body first enters the world: it collides as `other` (the caller's, alive while
    // the body is in the world; e.g. a fracture shard's hull) instead of its group shape. An
    // edit that reframes the body (dent, subdivide, a dynamic body's removePrimitives or
    // keepRemainder) makes the group shape its collision shape again, as before.
    void collideAs(btCollisionShape& other);
    // Before the body first enters the world (Plugin): the rigid body takes the group shape
    // unless collideAs gave it another.
    void readyToEnter();
    const geometry::PhysicalMesh& physicalMesh() const { return mesh_; }
    const BodySettings& settings() const { return settings_; }
    // What a break of a rigid body reads instead of every primitive's box: its group shape's
    // tree over the primitives, which keepRemainder edits with them. None for a deformable
    // body (its shape's boxes follow its particles) or one whose group shape is not built.
    // A rigid body that prepareFracture() prepared also carries its surface index
    // (fracture::SurfaceIndex), patched by keepRemainder and built again at the next call
    // after another edit. (A fragment is not prepared: most never break again, and building
    // one in its parent's break would cost that break what its own break saves.)
    fracture::PrimitiveIndex fractureIndex() const;
    // A rigid body about to be broken (FractureSystem::add): its surface index is built now, in
    // the body's set-up, rather than in its first break (the 16,000-primitive car shell:
    // ~2 M instructions, ~190 page faults), and its whole-body arrays get room for what breaks
    // add (no reallocation in the break); its welder and world faces are made here too. Nothing
    // for a deformable body.
    void prepareFracture();

    // Where mesh coordinates are now: body transform times the body-from-mesh offset.
    // (A soft body's mesh coordinates are the rest pose; its particles carry the motion.)
    btTransform meshTransform() const;
    // Mesh coordinates -> the rigid body's frame (centre of mass, principal axes; a static body
    // that lost primitives keeps the frame it had, see removePrimitives).
    const Eigen::Isometry3d& meshToBody() const { return meshToBody_; }
    // The visual mesh in world coordinates, welded from the primitives' current vertices
    // (source 000 §3.4); a soft body's primitives are deformed by D = A Ā⁻¹ first (§3.3).
    // Recomputed when the body moved or deformed since the last call. A body's first call also
    // builds its vertex welder and copies its faces (O(primitive vertices + faces)), unless an
    // edit or prepareFracture() did already: a break's fragments pay that when first shown.
    const geometry::VisualMesh& visualMesh();

    Deformation deformation() const { return settings_.deformation; }
    // The oriented-particle solver (null for Deformation::None). Particles are in mesh
    // coordinates for a plastic body (its rest pose) and in world coordinates for a soft one.
    oriented::OrientedSolver* solver() { return solver_.get(); }
    const oriented::OrientedSolver* solver() const { return solver_.get(); }
    // Holds these primitives in place in every deformation (joint-box attachments).
    void fixPrimitives(const std::vector<int>& primitives);
    // Largest rest-position change of any primitive since creation (m), and dents applied.
    double dentDepthMax() const { return dentDepthMax_; }
    int plasticEvents() const { return plasticEvents_; }
    // Warnings about this body (e.g. a primitive graph of several components).
    const std::vector<std::string>& warnings() const { return warnings_; }

    // Plastic body: applies dents (offsets in mesh coordinates), makes the result the new rest
    // shape, and rebuilds shape, centre of mass and inertia so that the undented part stays
    // where it was and velocities at every point are kept. The body must be out of the world
    // while this runs (the shape is replaced).
    oriented::PlasticResult dent(std::span<const oriented::Dent> dents);
    // Rigid body: removes the primitives at `removed` (indices into physicalMesh()'s
    // primitives); the others keep their order, their vertex ids and, in the group shape,
    // their child hulls. `faces` (in the current visual vertex ids) and `mass` are the rest's
    // visual surface and mass properties; visual vertices no face uses any more stay, unused,
    // where they are. The name stays. A static body keeps its frame (Bullet gives it no mass,
    // so the frame need not follow the centre of mass); a dynamic one moves its frame to the
    // rest's centre of mass and principal axes and takes the rest's mass and inertia and the
    // velocity its old motion has there (as after a dent). The body must be out of the world
    // while this runs (the shape's pairs are keyed by primitive index). Throws
    // shatter::InputError for a deformable body or a bad index.
    // The faces are copied into the storage of the faces the body had (a shrink's surface is
    // mostly the one before). The visual mesh after it is the one a fresh welder of the rest
    // gives (VertexWelder::removePrimitives edits the body's), bit for bit.
    void removePrimitives(const std::vector<int>& removed, const geometry::FaceList& faces,
                          const geometry::MassProperties& mass);
    // Rigid or plastic body: replaces the physical mesh by `mesh`, the same body cut finer
    // (fracture::subdivideMesh, in the current rest coordinates), where parents[i] is the
    // primitive of the old mesh that primitive i came from and the first `kept` primitives are
    // old ones unchanged, in increasing order. Same btRigidBody; the group shape keeps the
    // kept primitives' hulls and builds the others'; visual mesh, mass properties and (plastic)
    // particles are rebuilt; a particle is fixed when its parent was; the body frame moves to
    // the new centre of mass as after a dent, so momentum and the mesh's place are kept. The
    // body must be out of the world while this runs. Throws shatter::InputError for a soft body
    // or parents that do not match.
    void subdivide(geometry::PhysicalMesh mesh, const std::vector<int>& parents, int kept);
    // Rigid body: becomes the rest of a fracture (source 000 §3.6) in place:
    // fracture::applyRemainderEdit on its physical mesh, and the group shape drops the lost
    // primitives and adds the cut pieces in the same places (GroupShape::fillPrimitives: the
    // pieces take the lost primitives' places, the last survivors fill the holes left)
    // without touching the other hulls. The frame follows
    // as in removePrimitives. The body must be out of the world while this runs. Throws
    // shatter::InputError for a deformable body. The body's mesh takes `pieces`, the edit's
    // added pieces moved out of it by the caller (`keepRemainder(edit, std::move(edit.added))`:
    // moved, not copied), and reads the rest of the edit. `touched`: how far the edit's
    // touched connections are checked (fracture::TouchedList; FractureSystem passes
    // fractureMesh's own edit of this body unchanged, found from every connection).
    void keepRemainder(const fracture::RemainderEdit& edit, std::vector<geometry::ConvexPolyhedron>&& pieces,
                       fracture::TouchedList touched = fracture::TouchedList::Checked);
    // Soft body: one solver step with these contacts (and the Bullet bodies they couple to,
    // whose corrections the solver writes into `bodies`), or `substeps` steps of dt with them
    // (OrientedSolver::step), then the group shape is refitted to the particles' poses in place
    // (GroupShape::setPrimitivePoses): the body stays in the world; the caller updates its
    // broadphase box and clears its manifolds.
    void advanceSoft(double dt, std::span<const oriented::ParticleContact> contacts,
                     std::span<oriented::ContactBody> bodies = {}, int substeps = 1);
    // Soft body: places the group shape where the particles are now (after they were set from
    // outside, e.g. a torn part taking its parent's particles); the caller updates its
    // broadphase box.
    void refitSoft();
    // Soft body: a tear that leaves it in one piece, in place (fracture::openMesh): the
    // connections flagged in `broken` go and the global ids along them split; its particles,
    // solver state, shape, joints and place in the world stay, and only the solver's groups of
    // the broken connections' particles change. Returns nullopt, changing nothing, when the
    // connections left do not hold the body together. Throws shatter::InputError naming the
    // body for a body that is not soft.
    std::optional<fracture::MeshOpening> open(const std::vector<bool>& broken);
    // Soft body that parts: its mesh torn at `broken` (fracture::tearMesh), the primitives
    // moved into the parts instead of copied. The body's mesh is then left without primitive
    // shapes until it becomes one of the parts (keepPart), which must come before anything
    // else reads them (its particles, shape and settings stay as they were). Throws
    // shatter::InputError naming the body for a body that is not soft (or as tearMesh does,
    // then changing nothing).
    fracture::TearResult tearApart(const std::vector<bool>& broken);
    // Soft body: becomes `part`, one part of a tear of it (fracture::tearMesh), in place, where
    // parents[i] (strictly increasing) is the primitive of the current mesh that the part's
    // primitive i is. Same id and btRigidBody (its joints are the caller's); the group shape
    // drops the other primitives and keeps the part's hulls (GroupShape::removePrimitives);
    // each particle keeps its parent's pose, velocity, spin and fixed flag, and the shape stays
    // where the particles were last fitted (refitSoft: a tear comes right after the soft step,
    // the particles not moved since); name, solver
    // (groups, no warm start), welder, faces and mass properties are those of a new body made
    // from `part`, so the result is the body a tear would build, without building its shape.
    // The body must be out of the world while this runs. Throws shatter::InputError naming the
    // body for a body that is not soft or parents that do not match.
    void keepPart(geometry::PhysicalMesh part, const std::vector<int>& parents);
    // Soft body: particle i takes the pose, velocity, spin and fixed flag of from[parents[i]]
    // (the same primitive in another body, e.g. the body it was torn from), and the group
    // shape is placed there (refitSoft). Throws shatter::InputError naming the body for a body
    // that is not soft or parents that do not match.
    void takeParticles(const oriented::OrientedParticles& from, const std::vector<int>& parents);
    // A body made by the part constructor, once in the world: its shape's box goes where its
    // primitives are (GroupShape::fitBox); the caller updates its broadphase box.
    void fitShapeBox() { group().fitBox(); }
    // Soft body: each primitive's pose (rest coordinates → world) as last fitted.
    const std::vector<Eigen::Isometry3d>& softPoses() const { return softPoses_; }

private:
    // The group shape, built from unbuilt_ at the first call.
    GroupShape& group() const;
    void makeSolver(const Eigen::Isometry3d& meshPose);
    // After mesh_.primitives were replaced or edited: a welder for them, and the soft body's
    // vertex offsets dropped (they follow the welder's layout).
    void primitivesChanged();
    // The btRigidBody of the shape, the mesh at `meshPose` (a soft body's at the origin);
    // `moments`: mesh_.mass's principal moments.
    void makeRigidBody(const btTransform& meshPose, const Eigen::Vector3d& moments);
    void settleWorldFaces();
    void settleWelder();
    // Moves the body frame to mesh_.mass's centre and principal axes, the mesh staying where it
    // is; a dynamic body takes the new mass and inertia and the velocity at its new centre.
    void reframe();
    // keepRemainder, with a weld not as the body stands: world positions of the first `count`
    // visual vertices no primitive carries, from their rest positions (toWorld: mesh -> world).
    void placeUncarriedVertices(const Eigen::Isometry3d& toWorld, size_t count);
    // Each primitive's pose (rest coordinates -> world) from its particle, for a soft body.
    void particlePoses(std::vector<Eigen::Isometry3d>& poses) const;
    // Particle i takes from[parents[i]]'s pose, velocity, spin and fixed flag.
    void copyParticles(const oriented::OrientedParticles& from, const std::vector<int>& parents);

    int id_;
    geometry::PhysicalMesh mesh_;
    BodySettings settings_;
    Eigen::Isometry3d meshToBody_;      // mesh coordinates -> principal frame at the centre of mass
    // Primitives in the shape frame (the body frame at creation). A rigid or plastic body's
    // shape is built on demand (group()); until then its primitives wait in unbuilt_.
    mutable std::unique_ptr<GroupShape> shape_;
    mutable std::vector<geometry::ConvexPolyhedron> unbuilt_;
    // A prepared rigid body's surface index (see fractureIndex), null after an edit other
    // than keepRemainder's (which patches it) until the next break needs it.
    mutable std::unique_ptr<fracture::SurfaceIndex> surfaceIndex_;
    bool keepsSurfaceIndex_ = false; // prepareFracture() was called
    // Storage keepRemainder's fracture::applyRemainderEdit works in (the rest's connection
    // list, its primitive, face and id maps): the same blocks from break to break.
    fracture::RemainderScratch remainderScratch_;
    // After a dent the body frame moves to the new centre of mass; the group shape keeps its
    // frame and sits in this one-child compound at bodyFromShape_, so a dent replaces only the
    // moved primitives instead of rebuilding every one.
    std::unique_ptr<FramedShape> framed_; // remembers its contact breaking threshold (FramedShape.h)
    Eigen::Isometry3d meshToShape_ = Eigen::Isometry3d::Identity();
    Eigen::Isometry3d bodyFromShape_ = Eigen::Isometry3d::Identity();
    // Shatter's, unless the application deletes them (Watched.h): a deleted rigid body calls
    // whatever onRigidBodyDeleted set; a deleted motion state is just let go.
    WatchedPtr<btDefaultMotionState> motionState_;
    WatchedPtr<btRigidBody> body_;
    btRigidBody* rigid_ = nullptr; // body_'s object, valid also while someone else deletes it
    std::function<void(VisualBody&)> rigidBodyDeleted_;
    geometry::VertexWelder welder_;
    bool welderOwed_ = true; // welder_ is still to be built for the primitives (settleWelder)
    geometry::VisualMesh world_;
    // world_'s faces and crack marks are still to be copied from the mesh's (settleWorldFaces).
    bool worldFacesOwed_ = true;
    btTransform weldedAt_;
    bool welded_ = false;
    std::unique_ptr<oriented::OrientedSolver> solver_;
    std::vector<Eigen::Vector3d> originalRest_; // particle rest positions at creation
    // A soft body's rest vertex offsets, made on the first visualMesh() after the welder was
    // (re)made for the primitives; the deformed vertices, flat, in the welder's layout.
    std::optional<oriented::PrimitiveDeformation> primitiveDeformation_;
    std::vector<Eigen::Vector3d> deformedVertices_;
    std::vector<Eigen::Isometry3d> softPoses_;
    std::vector<std::string> warnings_;
    double dentDepthMax_ = 0.0;
    int plasticEvents_ = 0;
};

} // namespace shatter
