#include "bullet_ext/VisualBody.h"

#include "bullet_ext/Convert.h"
#include "plugin/geometry/InputError.h"

#include <LinearMath/btDefaultMotionState.h>
#include <cmath>
#include <sstream>

namespace shatter {

namespace {

bool finite(const btTransform& t) {
    for (int i = 0; i < 3; ++i)
        if (!std::isfinite(t.getOrigin()[i]) || !std::isfinite(t.getBasis()[i].x()) ||
            !std::isfinite(t.getBasis()[i].y()) || !std::isfinite(t.getBasis()[i].z()))
            return false;
    return true;
}

void checkSetting(const std::string& body, const char* what, double value, double lowest, bool inclusive) {
    const bool ok = std::isfinite(value) && (inclusive ? value >= lowest : value > lowest);
    if (!ok) {
        std::ostringstream msg;
        msg << "body '" << body << "': " << what << " must be " << (inclusive ? ">= " : "> ") << lowest
            << " and finite, got " << value;
        throw InputError(msg.str());
    }
}

void checkInputs(const geometry::PhysicalMesh& mesh, const BodySettings& s, const btTransform& pose) {
    if (!finite(pose)) throw InputError("body '" + mesh.name + "': pose has a non-finite value");
    const double det = double(pose.getBasis().determinant());
    if (std::abs(det - 1.0) > 1e-3) {
        std::ostringstream msg;
        msg << "body '" << mesh.name << "': pose rotation is not a rotation (determinant " << det << ")";
        throw InputError(msg.str());
    }
    if (mesh.primitives.empty()) throw InputError("body '" + mesh.name + "': has no primitives");
    checkSetting(mesh.name, "mass", mesh.mass.mass, 0.0, false);
    checkSetting(mesh.name, "friction", s.friction, 0.0, true);
    checkSetting(mesh.name, "restitution", s.restitution, 0.0, true);
    checkSetting(mesh.name, "rolling friction", s.rollingFriction, 0.0, true);
    checkSetting(mesh.name, "spinning friction", s.spinningFriction, 0.0, true);
    checkSetting(mesh.name, "collision margin", s.collisionMargin, 0.0, true);
    checkSetting(mesh.name, "joint breaking impulse", s.jointBreakingImpulse, 0.0, true);
    checkSetting(mesh.name, "linear damping", s.linearDamping, 0.0, true);
    checkSetting(mesh.name, "angular damping", s.angularDamping, 0.0, true);
}

// Rigid bodies in Bullet live in their centre-of-mass principal frame.
Eigen::Isometry3d principalFrameFromMesh(const geometry::MassProperties& mass) {
    const auto principal = mass.principal();
    Eigen::Isometry3d meshToBody = Eigen::Isometry3d::Identity();
    meshToBody.linear() = principal.axes.transpose();
    meshToBody.translation() = -(principal.axes.transpose() * mass.centerOfMass);
    return meshToBody;
}

std::vector<geometry::ConvexPolyhedron> moved(const std::vector<geometry::ConvexPolyhedron>& primitives,
                                              const Eigen::Isometry3d& t) {
    std::vector<geometry::ConvexPolyhedron> out;
    out.reserve(primitives.size());
    for (const auto& p : primitives) out.push_back(p.transformed(t));
    return out;
}

} // namespace

VisualBody::VisualBody(int id, geometry::PhysicalMesh mesh, const BodySettings& settings, const btTransform& meshPose)
    : id_(id), mesh_(std::move(mesh)), settings_(settings),
      welder_(mesh_.primitives, int(mesh_.visual.positions.size())) {
    checkInputs(mesh_, settings_, meshPose);
    meshToBody_ = principalFrameFromMesh(mesh_.mass);
    shape_ = std::make_unique<GroupShape>(moved(mesh_.primitives, meshToBody_), settings_.collisionMargin);

    const double mass = settings_.dynamic ? mesh_.mass.mass : 0.0;
    const auto moments = mesh_.mass.principal().moments;
    const btVector3 inertia = settings_.dynamic ? toBullet(moments) : btVector3(0, 0, 0);
    motionState_ = std::make_unique<btDefaultMotionState>(meshPose * toBullet(meshToBody_.inverse()));
    btRigidBody::btRigidBodyConstructionInfo info(btScalar(mass), motionState_.get(), shape_.get(), inertia);
    info.m_friction = btScalar(settings_.friction);
    info.m_restitution = btScalar(settings_.restitution);
    info.m_rollingFriction = btScalar(settings_.rollingFriction);
    info.m_spinningFriction = btScalar(settings_.spinningFriction);
    info.m_linearDamping = btScalar(settings_.linearDamping);
    info.m_angularDamping = btScalar(settings_.angularDamping);
    body_ = std::make_unique<btRigidBody>(info);
    world_.faces = mesh_.visual.faces;
}

btTransform VisualBody::meshTransform() const { return body_->getWorldTransform() * toBullet(meshToBody_); }

const geometry::VisualMesh& VisualBody::visualMesh() {
    const btTransform& now = body_->getWorldTransform();
    if (!welded_ || !(now == weldedAt_)) {
        welder_.weld(shape_->primitives(), toEigen(now), world_.positions);
        weldedAt_ = now;
        welded_ = true;
    }
    return world_;
}

} // namespace shatter
