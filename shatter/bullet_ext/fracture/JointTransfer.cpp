#include <shatter/bullet_ext/fracture/JointTransfer.h>

#include <shatter/bullet_ext/Joints.h>
#include <shatter/bullet_ext/System.h>
#include <shatter/bullet_ext/VisualBody.h>
#include <shatter/plugin/geometry/Connectivity.h>
#include <shatter/plugin/geometry/JointBoxes.h>

#include <algorithm>

namespace shatter {

namespace {

std::vector<const geometry::PhysicalMesh*> pointers(const std::vector<geometry::PhysicalMesh>& meshes) {
    std::vector<const geometry::PhysicalMesh*> out;
    out.reserve(meshes.size());
    for (const auto& mesh : meshes) out.push_back(&mesh);
    return out;
}

} // namespace

std::vector<int> fragmentsTouchingBox(const std::vector<geometry::PhysicalMesh>& fragments,
                                      const geometry::JointBox& box, double tolerance) {
    return fragmentsTouchingBox(pointers(fragments), box, tolerance);
}

std::vector<int> fragmentsTouchingBox(const std::vector<const geometry::PhysicalMesh*>& fragments,
                                      const geometry::JointBox& box, double tolerance) {
    const geometry::ConvexPolyhedron probe = geometry::boxPolyhedron({box.pose, box.halfExtents});
    const geometry::Aabb reach = probe.bounds().inflated(tolerance);
    std::vector<int> out;
    for (int k = 0; k < int(fragments.size()); ++k) {
        const auto& primitives = fragments[size_t(k)]->primitives;
        const bool touches = std::any_of(primitives.begin(), primitives.end(), [&](const auto& p) {
            return p.bounds().overlaps(reach) && geometry::withinTolerance(p, probe, tolerance);
        });
        if (touches) out.push_back(k);
    }
    return out;
}

int transferJoints(SystemContext& context, VisualBody& parent, const std::vector<VisualBody*>& bodies,
                   const std::vector<geometry::PhysicalMesh>& meshes) {
    return transferJoints(context, parent, bodies, pointers(meshes));
}

int transferJoints(SystemContext& context, VisualBody& parent, const std::vector<VisualBody*>& bodies,
                   const std::vector<const geometry::PhysicalMesh*>& meshes) {
    const double tolerance = parent.physicalMesh().contactTolerance;
    int copies = 0;
    for (const Joint* joint : context.jointsOf(parent)) {
        if (joint->broken()) continue; // a broken joint holds nothing any more
        const bool parentIsA = &joint->bodyA() == &parent;
        VisualBody& other = const_cast<VisualBody&>(parentIsA ? joint->bodyB() : joint->bodyA());
        for (int k : fragmentsTouchingBox(meshes, joint->box(), tolerance)) {
            VisualBody& body = *bodies[size_t(k)];
            const Joint& copy = parentIsA ? context.addJoint(joint->box(), body, other)
                                          : context.addJoint(joint->box(), other, body);
            context.push(Event{EventType::JointRecreated, body.id(), copy.id(), 0.0, copy.name(), joint->id(), {}});
            ++copies;
        }
    }
    return copies;
}

} // namespace shatter
