#pragma once
// A Shatter body in a Bullet world: one btRigidBody with a GroupShape, and the visual mesh
// that follows its primitives.
#include "bullet_ext/BodySettings.h"
#include "bullet_ext/GroupShape.h"
#include "plugin/geometry/PhysicalMesh.h"

#include <BulletDynamics/Dynamics/btRigidBody.h>
#include <LinearMath/btDefaultMotionState.h>
#include <memory>

namespace shatter {

class VisualBody {
public:
    VisualBody(int id, geometry::PhysicalMesh mesh, const BodySettings& settings, const btTransform& meshPose);

    int id() const { return id_; }
    const std::string& name() const { return mesh_.name; }
    btRigidBody& rigidBody() { return *body_; }
    const btRigidBody& rigidBody() const { return *body_; }
    const GroupShape& shape() const { return *shape_; }
    const geometry::PhysicalMesh& physicalMesh() const { return mesh_; }
    const BodySettings& settings() const { return settings_; }

    // Where mesh coordinates are now: body transform times the fixed body-from-mesh offset.
    btTransform meshTransform() const;
    // The visual mesh in world coordinates, welded from the primitives' current vertices
    // (source 000 §3.4). Recomputed when the body has moved since the last call.
    const geometry::VisualMesh& visualMesh();

private:
    int id_;
    geometry::PhysicalMesh mesh_;
    BodySettings settings_;
    Eigen::Isometry3d meshToBody_;      // mesh coordinates -> principal frame at the centre of mass
    std::unique_ptr<GroupShape> shape_; // primitives in the body frame
    std::unique_ptr<btDefaultMotionState> motionState_;
    std::unique_ptr<btRigidBody> body_;
    geometry::VertexWelder welder_;
    geometry::VisualMesh world_;
    btTransform weldedAt_;
    bool welded_ = false;
};

} // namespace shatter
