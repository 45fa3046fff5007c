#include <shatter/bullet_ext/VisualBody.h>

#include <shatter/bullet_ext/Convert.h>
#include <shatter/plugin/common/InputError.h>
#include <shatter/plugin/common/SettingCheck.h>
#include <shatter/plugin/geometry/HoleFilling.h>
#include <shatter/plugin/oriented/PrimitiveDeformation.h>

#include <LinearMath/btDefaultMotionState.h>
#include <algorithm>
#include <cmath>
#include <functional>
#include <sstream>

namespace shatter {

namespace {

void checkInputs(const geometry::PhysicalMesh& mesh, const BodySettings& s, const btTransform& pose) {
    if (!finite(pose)) throw InputError("body '" + mesh.name + "': pose has a non-finite value");
    const double det = double(pose.getBasis().determinant());
    if (std::abs(det - 1.0) > 1e-3) {
        std::ostringstream msg;
        msg << "body '" << mesh.name << "': pose rotation is not a rotation (determinant " << det << ")";
        throw InputError(msg.str());
    }
    if (mesh.primitives.empty()) throw InputError("body '" + mesh.name + "': has no primitives");
    requirePositive(mesh.name, "mass", mesh.mass.mass);
    s.check(mesh.name);
}

// Rigid bodies in Bullet live in their centre-of-mass principal frame (`principal`: the
// principal frame of `mass`, computed once where the caller needs its moments too).
Eigen::Isometry3d principalFrameFromMesh(const geometry::MassProperties& mass,
                                         const geometry::MassProperties::Principal& principal) {
    Eigen::Isometry3d meshToBody = Eigen::Isometry3d::Identity();
    meshToBody.linear() = principal.axes.transpose();
    meshToBody.translation() = -(principal.axes.transpose() * mass.centerOfMass);
    return meshToBody;
}

Eigen::Isometry3d principalFrameFromMesh(const geometry::MassProperties& mass) {
    return principalFrameFromMesh(mass, mass.principal());
}

// `faces` into `to`, each face into the storage of the face at its place: a shrink's surface
// is mostly the faces it had, and a vector allocated (and the old one freed) per face cost
// 23 M instructions at three shrinks of the 55k-tet Spot statue.
void assignFaces(std::vector<std::vector<int>>& to, const geometry::FaceList& faces) {
    to.resize(faces.size());
    for (size_t f = 0; f < faces.size(); ++f) to[f].assign(faces[f].begin(), faces[f].end()); // reuses its storage
}

// The primitives moved rigidly, their planes, bounds and mass properties moved with them
// rather than computed again from the moved vertices (a fracture makes bodies of thousands).
// Each is written in its place in the vector (assignMoved into an empty one, the bits of
// moved()), not built aside and moved in: 10.31 -> 10.07 M instructions over five 64-cell
// breaks of the 16k shell (callgrind).
std::vector<geometry::ConvexPolyhedron> moved(const std::vector<geometry::ConvexPolyhedron>& primitives,
                                              const Eigen::Isometry3d& t) {
    std::vector<geometry::ConvexPolyhedron> out(primitives.size());
    for (size_t i = 0; i < primitives.size(); ++i) out[i].assignMoved(primitives[i], t);
    return out;
}

// Capacity for what a few breaks add to a whole-body array (every break adds visual vertices;
// one that adds more pieces to the rest than it removes adds primitives): grown by
// reallocation, such a break copied each array (the primitives, the visual positions and
// faces, twice) into fresh pages. Reserved room is address space only until a break writes
// there.
template <class Vector>
void reserveRoom(Vector& v, size_t size) {
    v.reserve(size + size / 4 + 64);
}

} // namespace

VisualBody::VisualBody(int id, geometry::PhysicalMesh mesh, const BodySettings& settings, const btTransform& meshPose)
    : id_(id), mesh_(std::move(mesh)), settings_(settings) {
    checkInputs(mesh_, settings_, meshPose);
    // Once for the frame and the rigid body's inertia (an eigensolve, ~1.4 K instructions:
    // a fracture's event makes a body per fragment).
    const geometry::MassProperties::Principal principal = mesh_.mass.principal();
    meshToBody_ = principalFrameFromMesh(mesh_.mass, principal);
    meshToShape_ = meshToBody_;
    if (settings_.deformation != Deformation::None) makeSolver(toEigen(meshPose));
    const bool soft = settings_.deformation == Deformation::Soft;
    // A soft body's primitives sit where its particles are, in world coordinates, on a
    // kinematic body at the origin whose contacts Bullet detects but does not solve: the
    // soft step solves them with the particles (DeformationSystem).
    std::vector<geometry::ConvexPolyhedron> primitives;
    if (soft) {
        particlePoses(softPoses_);
        for (size_t i = 0; i < mesh_.primitives.size(); ++i) primitives.push_back(mesh_.primitives[i].moved(softPoses_[i]));
    }
    if (soft) {
        shape_ = std::make_unique<GroupShape>(std::move(primitives), settings_.rigidBody.collisionMargin);
        shape_->setContactPerPrimitive(true);
    } else {
        unbuilt_ = moved(mesh_.primitives, meshToBody_); // group() builds the shape when needed
    }
    makeRigidBody(meshPose, principal.moments);
}

GroupShape& VisualBody::group() const {
    if (!shape_) {
        shape_ = std::make_unique<GroupShape>(std::move(unbuilt_), settings_.rigidBody.collisionMargin);
        unbuilt_.clear();
    }
    return *shape_;
}

fracture::PrimitiveIndex VisualBody::fractureIndex() const {
    fracture::PrimitiveIndex index;
    if (settings_.deformation != Deformation::None) return index;
    if (keepsSurfaceIndex_ && !surfaceIndex_) surfaceIndex_ = std::make_unique<fracture::SurfaceIndex>(mesh_);
    index.surface = surfaceIndex_.get();
    // A fragment that collides as its hull has no group shape yet, and building one to cut a
    // few primitives would cost more than the grid does.
    if (!shape_) return index;
    // The shape's primitives are the mesh's moved by meshToShape_, item for item.
    index.tree = &group().tree();
    index.treeToMesh = meshToShape_.inverse();
    return index;
}

void VisualBody::prepareFracture() {
    if (settings_.deformation != Deformation::None) return;
    keepsSurfaceIndex_ = true;
    if (!surfaceIndex_) surfaceIndex_ = std::make_unique<fracture::SurfaceIndex>(mesh_);
    settleWorldFaces(); // in the set-up: a break edits them in place (keepRemainder)
    settleWelder();     // likewise
    reserveRoom(mesh_.primitives, mesh_.primitives.size());
    reserveRoom(mesh_.sourceFace, mesh_.sourceFace.size());
    reserveRoom(mesh_.visual.positions, mesh_.visual.positions.size());
    reserveRoom(mesh_.visual.faces, mesh_.visual.faces.size());
    reserveRoom(world_.positions, mesh_.visual.positions.size()); // welded at the first visualMesh()
    reserveRoom(world_.faces, world_.faces.size());
    // Here, so that the first break too finds them (see RemainderScratch::reserveFor).
    remainderScratch_.reserveFor(mesh_.primitives.size(), mesh_.connections.size(), mesh_.visual.faces.size(),
                                 size_t(std::max(mesh_.globalIdCount, 0)));
}

void VisualBody::collideAs(btCollisionShape& other) {
    // In the world, Bullet's pairs keep the algorithms made for the old shape (a group's, which
    // would read the hull as a group).
    if (rigid_->getBroadphaseHandle())
        throw InputError("body '" + mesh_.name + "': collideAs() is only for a body that has not entered the world");
    rigid_->setCollisionShape(&other);
}

void VisualBody::readyToEnter() {
    if (!rigid_->getCollisionShape()) rigid_->setCollisionShape(&group());
}

VisualBody::VisualBody(int id, VisualBody& parent, geometry::PhysicalMesh part, const std::vector<int>& parents,
                       const BodySettings& settings)
    : id_(id), mesh_(std::move(part)), settings_(settings) {
    if (settings_.deformation != Deformation::Soft || parent.settings_.deformation != Deformation::Soft)
        throw InputError("body '" + mesh_.name + "': a part taken from body '" + parent.name() +
                         "' needs both soft (Deformation::Soft)");
    checkInputs(mesh_, settings_, btTransform::getIdentity());
    if (parents.size() != mesh_.primitives.size() || !std::is_sorted(parents.begin(), parents.end(), std::less_equal<>()) ||
        std::any_of(parents.begin(), parents.end(), [&](int j) { return j < 0 || j >= parent.solver_->particles().size(); }))
        throw InputError("body '" + mesh_.name + "': needs one primitive of body '" + parent.name() +
                         "' per primitive, strictly increasing");
    const geometry::MassProperties::Principal principal = mesh_.mass.principal();
    meshToBody_ = principalFrameFromMesh(mesh_.mass, principal);
    meshToShape_ = meshToBody_;
    // As a new body of the part whose particles then take the parent's (takeParticles), with
    // the parent's poses and hulls where the refit would put them again.
    makeSolver(Eigen::Isometry3d::Identity());
    copyParticles(parent.solver_->particles(), parents);
    softPoses_.reserve(parents.size());
    for (int j : parents) softPoses_.push_back(parent.softPoses_[size_t(j)]);
    shape_ = std::make_unique<GroupShape>(parent.group(), parents, mesh_.primitives);
    makeRigidBody(btTransform::getIdentity(), principal.moments);
}

void VisualBody::makeRigidBody(const btTransform& meshPose, const Eigen::Vector3d& moments) {
    const bool soft = settings_.deformation == Deformation::Soft;
    const bool dynamic = settings_.dynamic && !soft;
    const double mass = dynamic ? mesh_.mass.mass : 0.0;
    const btVector3 inertia = dynamic ? toBullet(moments) : btVector3(0, 0, 0);
    const btTransform start = soft ? btTransform::getIdentity() : meshPose * toBullet(meshToBody_.inverse());
    motionState_.reset(std::make_unique<Watched<btDefaultMotionState>>(start));
    // No collision shape yet for a rigid or plastic body: readyToEnter or collideAs gives it.
    btRigidBody::btRigidBodyConstructionInfo info(btScalar(mass), motionState_.get(), shape_.get(), inertia);
    settings_.rigidBody.applyTo(info);
    body_.reset(std::make_unique<Watched<btRigidBody>>(info), [this] {
        if (rigidBodyDeleted_) rigidBodyDeleted_(*this);
    });
    rigid_ = body_.get();
    if (soft) {
        rigid_->setCollisionFlags(rigid_->getCollisionFlags() | btCollisionObject::CF_KINEMATIC_OBJECT |
                                  btCollisionObject::CF_NO_CONTACT_RESPONSE);
        rigid_->setActivationState(DISABLE_DEACTIVATION);
    }
}

void VisualBody::settleWelder() {
    // Built for the primitives when first needed (visualMesh() or an edit), not when the body
    // is made: a fracture makes a body per fragment, and their welders (ten arrays each) were
    // 3.4 M of the 202.7 M instructions of five 64-cell events of the 16k shell; the first
    // visualMesh() of each fragment pays it now. The same welder: until then the primitives
    // keep their ids (only an edit changes them, and every edit settles it first or makes it anew).
    if (!welderOwed_) return;
    welder_ = geometry::VertexWelder(mesh_.primitives, int(mesh_.visual.positions.size()));
    welderOwed_ = false;
}

void VisualBody::settleWorldFaces() {
    // The world mesh's faces are the mesh's: a new body copies them when visualMesh() (or an
    // edit of them) first needs them, not when it is made. A fracture makes a body per
    // fragment, and the copy (a vector a face) was 2.7 M of the 202.7 M instructions of five
    // 64-cell events of the 16k shell; the first visualMesh() of each fragment pays it now.
    if (!worldFacesOwed_) return;
    world_.faces = mesh_.visual.faces;
    world_.crackFace = mesh_.visual.crackFace;
    worldFacesOwed_ = false;
}

void VisualBody::makeSolver(const Eigen::Isometry3d& meshPose) {
    const int components = mesh_.componentCount();
    if (components > 1)
        warnings_.push_back("body '" + mesh_.name + "': its primitives form " + std::to_string(components) +
                            " unconnected parts; each part is simulated on its own");
    oriented::OrientedParticles particles = oriented::particlesFromPrimitives(mesh_.primitives, mesh_.density, mesh_.name);
    if (solver_) // a body made anew in place: the old solver's memory serves (OrientedSolver::rebuild)
        solver_->rebuild(mesh_.name, std::move(particles), mesh_.connections, settings_.solver);
    else
        solver_ = std::make_unique<oriented::OrientedSolver>(mesh_.name, std::move(particles), mesh_.connections,
                                                             settings_.solver);
    auto& p = solver_->particles();
    originalRest_ = p.restPosition;
    if (settings_.deformation != Deformation::Soft) return;
    const Eigen::Quaterniond turn(meshPose.linear());
    for (int i = 0; i < p.size(); ++i) {
        p.position[i] = meshPose * p.position[i];
        p.orientation[i] = turn;
    }
}

btTransform VisualBody::meshTransform() const { return rigid_->getWorldTransform() * toBullet(meshToBody_); }

void VisualBody::fixPrimitives(const std::vector<int>& primitives) {
    if (!solver_) return;
    for (int i : primitives)
        if (i >= 0 && i < solver_->particles().size()) solver_->particles().fixed[i] = true;
}

void VisualBody::particlePoses(std::vector<Eigen::Isometry3d>& poses) const {
    const auto& p = solver_->particles();
    poses.resize(size_t(p.size()), Eigen::Isometry3d::Identity());
    for (int i = 0; i < p.size(); ++i) {
        Eigen::Isometry3d& pose = poses[size_t(i)];
        pose.linear() = p.orientation[i].toRotationMatrix();
        pose.translation() = p.position[i] - pose.linear() * p.restPosition[i];
    }
}

oriented::PlasticResult VisualBody::dent(std::span<const oriented::Dent> dents) {
    if (settings_.deformation != Deformation::Plastic)
        throw InputError("body '" + mesh_.name + "': dent() needs a body with Deformation::Plastic");
    oriented::PlasticResult result = oriented::deformPlastically(*solver_, dents, settings_.plastic);
    if (result.moved.empty()) return result;
    std::vector<geometry::ConvexPolyhedron> inShape;
    inShape.reserve(result.moved.size());
    for (size_t k = 0; k < result.moved.size(); ++k) {
        auto& primitive = mesh_.primitives[result.moved[k]];
        primitive = primitive.transformed(result.motion[k]);
        inShape.push_back(primitive.transformed(meshToShape_));
    }
    group().replacePrimitives(result.moved, inShape);
    geometry::MassProperties total;
    for (const auto& primitive : mesh_.primitives) total += primitive.massProperties(mesh_.density);
    mesh_.mass = total;

    reframe();

    const auto& rest = solver_->particles().restPosition;
    for (size_t i = 0; i < rest.size(); ++i) dentDepthMax_ = std::max(dentDepthMax_, (rest[i] - originalRest_[i]).norm());
    ++plasticEvents_;
    return result;
}

void VisualBody::reframe() {
    // The mesh stays where it is; the body frame moves to the new centre of mass and principal
    // axes, and takes the velocity the old motion has at that point.
    const btTransform meshWorld = meshTransform();
    const btVector3 oldCentre = rigid_->getCenterOfMassPosition();
    const btVector3 v = rigid_->getLinearVelocity(), w = rigid_->getAngularVelocity();
    meshToBody_ = principalFrameFromMesh(mesh_.mass);
    bodyFromShape_ = meshToBody_ * meshToShape_.inverse();
    if (!framed_) {
        framed_ = std::make_unique<FramedShape>();
        framed_->addChildShape(toBullet(bodyFromShape_), &group());
    } else {
        framed_->updateChildTransform(0, toBullet(bodyFromShape_));
    }
    framed_->recalculateLocalAabb(); // the child's primitives moved too
    framed_->setMargin(group().getMargin());
    rigid_->setCollisionShape(framed_.get());
    welded_ = false;
    const btTransform bodyWorld = meshWorld * toBullet(meshToBody_.inverse());
    rigid_->setWorldTransform(bodyWorld);
    rigid_->setInterpolationWorldTransform(bodyWorld);
    if (motionState_) motionState_->setWorldTransform(bodyWorld);
    if (settings_.dynamic) {
        rigid_->setMassProps(btScalar(mesh_.mass.mass), toBullet(mesh_.mass.principal().moments));
        rigid_->updateInertiaTensor();
    }
    rigid_->setLinearVelocity(v + w.cross(bodyWorld.getOrigin() - oldCentre));
    rigid_->setAngularVelocity(w);
}

void VisualBody::removePrimitives(const std::vector<int>& removed, const geometry::FaceList& faces,
                                  const geometry::MassProperties& mass) {
    if (settings_.deformation != Deformation::None)
        throw InputError("body '" + mesh_.name + "': removePrimitives() needs a rigid body");
    settleWelder(); // it follows the removal
    // Where each primitive goes (-1: removed); the others close up in order.
    std::vector<int> to(mesh_.primitives.size(), 0);
    for (int i : removed) {
        if (i < 0 || i >= int(to.size()))
            throw InputError("body '" + mesh_.name + "': removePrimitives() has no primitive " + std::to_string(i));
        to[size_t(i)] = -1;
    }
    const size_t ids = mesh_.visual.positions.size();
    for (const int id : faces.indices())
        if (id < 0 || size_t(id) >= ids)
            throw InputError("body '" + mesh_.name + "': removePrimitives() has a face on vertex " + std::to_string(id) +
                             ", the visual mesh has " + std::to_string(ids));
    std::vector<int> gone; // the removed ones, ascending, each once
    gone.reserve(removed.size());
    for (size_t i = 0; i < to.size(); ++i)
        if (to[i] < 0) gone.push_back(int(i));
    // Visual vertices that no face will use keep the place the welder gives them now (they
    // stay in the list, so an exporter writes them where they are, never unset). Only those
    // no kept primitive carries: the next visualMesh() welds the others again (a weld of the
    // whole Spot statue before each shrink was 35 M instructions of three shrinks).
    const btTransform& now = rigid_->getWorldTransform();
    if (!welded_ || !(now == weldedAt_))
        welder_.weldCarriedOnlyBy(shapePrimitives(), gone, toEigen(now) * bodyFromShape_, world_.positions);
    group().removePrimitives(removed); // checks that some are left
    int kept = 0;
    for (int& t : to) t = t < 0 ? -1 : kept++;
    for (size_t i = 0; i < to.size(); ++i) {
        if (to[i] < 0 || to[i] == int(i)) continue;
        mesh_.primitives[to[i]] = std::move(mesh_.primitives[i]);
        mesh_.sourceFace[to[i]] = mesh_.sourceFace[i];
    }
    surfaceIndex_.reset(); // built again at the next break
    mesh_.primitives.erase(mesh_.primitives.begin() + kept, mesh_.primitives.end());
    mesh_.sourceFace.resize(size_t(kept));
    std::erase_if(mesh_.connections, [&](const auto& c) { return to[c.first] < 0 || to[c.second] < 0; });
    for (auto& [a, b] : mesh_.connections) {
        a = to[a];
        b = to[b];
    }
    assignFaces(mesh_.visual.faces, faces);
    mesh_.visual.crackFace.clear(); // the new faces come without crack flags
    mesh_.mass = mass;
    // The welder follows the removal (the one a new welder would be, without reading every
    // primitive's ids: 51 M instructions of three shrinks of the Spot statue).
    welder_.removePrimitives(mesh_.primitives, gone);
    primitiveDeformation_.reset();
    assignFaces(world_.faces, faces);
    world_.crackFace.clear();
    worldFacesOwed_ = false; // they are the mesh's now
    welded_ = false;
    // A static body has no mass in Bullet, so its frame need not follow the centre of mass.
    if (settings_.dynamic) reframe();
}

void VisualBody::subdivide(geometry::PhysicalMesh mesh, const std::vector<int>& parents, int kept) {
    if (settings_.deformation == Deformation::Soft)
        throw InputError("body '" + mesh_.name + "': subdivide() needs a rigid or plastic body");
    const int oldCount = int(mesh_.primitives.size());
    if (parents.size() != mesh.primitives.size() || kept < 0 || kept > int(parents.size()) ||
        std::any_of(parents.begin(), parents.end(), [&](int p) { return p < 0 || p >= oldCount; }) ||
        !std::is_sorted(parents.begin(), parents.begin() + kept, std::less_equal<>()))
        throw InputError("body '" + mesh_.name + "': subdivide() needs one parent primitive per new primitive, "
                         "the kept ones first in increasing order");
    // What each old particle carried: fixed (joint box) and how far dents moved it from creation.
    std::vector<char> fixed;
    std::vector<Eigen::Vector3d> drift;
    if (solver_) {
        const auto& p = solver_->particles();
        for (int i = 0; i < p.size(); ++i) {
            fixed.push_back(p.fixed[i]);
            drift.push_back(p.restPosition[i] - originalRest_[size_t(i)]);
        }
    }
    // The kept primitives keep their hulls in the group shape; the others go, the pieces come.
    std::unique_ptr<GroupShape> oldShape;
    std::unique_ptr<btCompoundShape> oldFramed; // the rigid body holds one of these until reframe()
    if (kept > 0) {
        std::vector<char> stays(size_t(oldCount), 0);
        for (int i = 0; i < kept; ++i) stays[size_t(parents[size_t(i)])] = 1;
        std::vector<int> removed;
        for (int p = 0; p < oldCount; ++p)
            if (!stays[size_t(p)]) removed.push_back(p);
        std::vector<geometry::ConvexPolyhedron> added;
        for (size_t i = size_t(kept); i < mesh.primitives.size(); ++i) added.push_back(mesh.primitives[i].transformed(meshToShape_));
        group().removePrimitives(removed, std::move(added));
    } else {
        oldShape = std::move(shape_);
        oldFramed = std::move(framed_);
        unbuilt_ = moved(mesh.primitives, meshToShape_); // built by reframe() below
    }
    mesh_ = std::move(mesh);
    primitivesChanged();
    worldFacesOwed_ = true;
    if (solver_) {
        makeSolver(Eigen::Isometry3d::Identity()); // a plastic body's particles live in rest coordinates
        auto& p = solver_->particles();
        for (int i = 0; i < p.size(); ++i) {
            p.fixed[i] = fixed[size_t(parents[size_t(i)])];
            originalRest_[size_t(i)] = p.restPosition[i] - drift[size_t(parents[size_t(i)])];
        }
    }
    reframe();
}

void VisualBody::keepRemainder(const fracture::RemainderEdit& edit, std::vector<geometry::ConvexPolyhedron>&& pieces,
                               fracture::TouchedList touched) {
    if (settings_.deformation != Deformation::None)
        throw InputError("body '" + mesh_.name + "': keepRemainder() needs a rigid body");
    settleWelder(); // it follows the edit
    // Visual vertices no primitive carries after the edit stay where they are now (the next
    // weld moves only carried ones): placed from their rest positions below, once the welder
    // knows which they are. Where the body is welded as it stands, they already are.
    const btTransform& now = rigid_->getWorldTransform();
    const bool placeUncarried = !welded_ || !(now == weldedAt_);
    const Eigen::Isometry3d toWorld = toEigen(meshTransform()); // the mesh stays where it is (reframe)
    const size_t visualBefore = mesh_.visual.positions.size(); // the edit appends after these
    const int added = int(pieces.size());
    // The mesh takes the pieces themselves; only the primitives the welder (built for them)
    // finds carrying a swapped id are asked for their ids.
    const std::vector<int> carriers = welder_.primitivesCarrying(fracture::swappedIds(edit));
    const geometry::HoleFilling slots =
        geometry::fillHoles(int(mesh_.primitives.size()), edit.removed, added);
    // The surface index follows the edit (read from the faces before it); dropped if the edit
    // is refused, so that it never holds an edit the body does not.
    try {
        if (surfaceIndex_) surfaceIndex_->patch(mesh_, edit);
        fracture::applyRemainderEdit(mesh_, edit, std::move(pieces), carriers, &remainderScratch_, touched);
    } catch (...) {
        surfaceIndex_.reset();
        throw;
    }
    // The places the mesh's primitives took, the pieces read from there (in the shape's frame).
    group().fillPrimitives(edit.removed, mesh_.primitives, added, meshToShape_);
    // The welder follows the same edit (the one a new welder would be, without reading every
    // primitive's ids).
    welder_.fillHoles(mesh_.primitives, edit.removed, slots, edit.idSwaps, int(mesh_.visual.positions.size()));
    if (placeUncarried) placeUncarriedVertices(toWorld, visualBefore);
    primitiveDeformation_.reset();
    // The same faces, without copying the kept ones; faces still owed are copied edited.
    if (!worldFacesOwed_) fracture::applyFaceEdit(world_, edit);
    welded_ = false;
    if (settings_.dynamic) reframe();
}

void VisualBody::placeUncarriedVertices(const Eigen::Isometry3d& toWorld, size_t count) {
    // Only the uncarried ones: the next weld (the only way out, visualMesh()) overwrites every
    // carried one. Placing all of a 16k-vertex rest at every break cost ~0.45 M instructions
    // (~35 a vertex), where the test is a load. The uncarried ones get the bits they got
    // when every vertex was placed. The edit only appends rest positions (ids from `count` up,
    // all carried by the cut pieces, which the weld places), so the first `count` are those
    // from before it.
    world_.positions.resize(count);
    // The welder lists them (a test of every visual id was ~1 M instructions of five breaks).
    // Through plain pointers: the vectors' own members would be reloaded after every store
    // (they might alias it).
    const Eigen::Vector3d* rest = mesh_.visual.positions.data();
    Eigen::Vector3d* world = world_.positions.data();
    for (const int i : welder_.uncarried())
        if (size_t(i) < count) world[i] = toWorld * rest[i];
}

void VisualBody::advanceSoft(double dt, std::span<const oriented::ParticleContact> contacts,
                             std::span<oriented::ContactBody> bodies, int substeps) {
    if (settings_.deformation != Deformation::Soft)
        throw InputError("body '" + mesh_.name + "': advanceSoft() needs a body with Deformation::Soft");
    solver_->step(dt, contacts, bodies, substeps);
    refitSoft();
}

void VisualBody::refitSoft() {
    if (settings_.deformation != Deformation::Soft)
        throw InputError("body '" + mesh_.name + "': refitSoft() needs a body with Deformation::Soft");
    particlePoses(softPoses_);
    group().setPrimitivePoses(mesh_.primitives, softPoses_);
    welded_ = false;
}

std::optional<fracture::MeshOpening> VisualBody::open(const std::vector<bool>& broken) {
    if (settings_.deformation != Deformation::Soft)
        throw InputError("body '" + mesh_.name + "': open() needs a body with Deformation::Soft");
    std::optional<fracture::MeshOpening> opening = fracture::openMesh(mesh_, broken);
    if (!opening) return opening;
    solver_->groups().removeConnections(solver_->particles(), opening->broken);
    primitivesChanged();
    if (!worldFacesOwed_) // else they are copied whole when asked for
        for (int f : opening->faces) world_.faces[size_t(f)] = mesh_.visual.faces[size_t(f)];
    welded_ = false;
    return opening;
}

fracture::TearResult VisualBody::tearApart(const std::vector<bool>& broken) {
    if (settings_.deformation != Deformation::Soft)
        throw InputError("body '" + mesh_.name + "': tearApart() needs a body with Deformation::Soft");
    return fracture::tearMesh(std::move(mesh_), broken);
}

void VisualBody::keepPart(geometry::PhysicalMesh part, const std::vector<int>& parents) {
    if (settings_.deformation != Deformation::Soft)
        throw InputError("body '" + mesh_.name + "': keepPart() needs a body with Deformation::Soft");
    const int oldCount = solver_->particles().size(); // one per primitive (tearApart took the primitives)
    if (parents.empty() || parents.size() != part.primitives.size() || parents.front() < 0 ||
        parents.back() >= oldCount || !std::is_sorted(parents.begin(), parents.end(), std::less_equal<>()))
        throw InputError("body '" + mesh_.name + "': keepPart() needs one parent primitive per part primitive, "
                         "strictly increasing");
    std::vector<char> stays(size_t(oldCount), 0);
    for (int p : parents) stays[size_t(p)] = 1;
    std::vector<int> removed;
    for (int p = 0; p < oldCount; ++p)
        if (!stays[size_t(p)]) removed.push_back(p);
    if (!removed.empty()) group().removePrimitives(removed); // the rest keep their hulls, in order
    mesh_ = std::move(part);
    primitivesChanged();
    worldFacesOwed_ = true;
    welded_ = false;
    meshToBody_ = principalFrameFromMesh(mesh_.mass);
    meshToShape_ = meshToBody_;
    // A new solver over the part (made in the old one's memory: its groups are megabytes,
    // fresh pages in the frame of the tear otherwise), its particles then put where the
    // parent's are.
    const oriented::OrientedParticles old = std::move(solver_->particles());
    warnings_.clear(); // they were about the mesh the body no longer is
    makeSolver(Eigen::Isometry3d::Identity());
    copyParticles(old, parents);
    // The kept hulls are already where these particles were last fitted (refitSoft after the
    // soft step), so only the poses close up like the primitives (parents increase).
    for (size_t i = 0; i < parents.size(); ++i) softPoses_[i] = softPoses_[size_t(parents[i])];
    softPoses_.resize(parents.size());
}

void VisualBody::takeParticles(const oriented::OrientedParticles& from, const std::vector<int>& parents) {
    if (settings_.deformation != Deformation::Soft)
        throw InputError("body '" + mesh_.name + "': takeParticles() needs a body with Deformation::Soft");
    if (parents.size() != size_t(solver_->particles().size()) ||
        std::any_of(parents.begin(), parents.end(), [&](int j) { return j < 0 || j >= from.size(); }))
        throw InputError("body '" + mesh_.name + "': takeParticles() needs one particle of `from` per particle");
    copyParticles(from, parents);
    refitSoft();
}

void VisualBody::copyParticles(const oriented::OrientedParticles& from, const std::vector<int>& parents) {
    oriented::OrientedParticles& to = solver_->particles();
    for (int i = 0; i < to.size(); ++i) {
        const int j = parents[size_t(i)];
        to.position[size_t(i)] = from.position[size_t(j)];
        to.orientation[size_t(i)] = from.orientation[size_t(j)];
        to.velocity[size_t(i)] = from.velocity[size_t(j)];
        to.angularVelocity[size_t(i)] = from.angularVelocity[size_t(j)];
        to.fixed[size_t(i)] = from.fixed[size_t(j)];
    }
}

void VisualBody::primitivesChanged() {
    surfaceIndex_.reset(); // built again at the next break
    welderOwed_ = true; // made for the new primitives when next needed (settleWelder)
    primitiveDeformation_.reset(); // made again on the next visualMesh()
}

const geometry::VisualMesh& VisualBody::visualMesh() {
    settleWorldFaces();
    settleWelder();
    const btTransform& now = rigid_->getWorldTransform();
    if (welded_ && now == weldedAt_) return world_;
    if (settings_.deformation == Deformation::Soft) {
        if (!primitiveDeformation_) primitiveDeformation_.emplace(solver_->particles(), mesh_.primitives);
        primitiveDeformation_->deformedVertices(*solver_, deformedVertices_);
        welder_.weld(deformedVertices_, Eigen::Isometry3d::Identity(), world_.positions);
    } else {
        welder_.weld(shapePrimitives(), toEigen(now) * bodyFromShape_, world_.positions);
    }
    weldedAt_ = now;
    welded_ = true;
    return world_;
}

} // namespace shatter
