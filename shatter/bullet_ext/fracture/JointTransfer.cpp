#include <shatter/bullet_ext/fracture/JointTransfer.h>

#include <shatter/plugin/geometry/Connectivity.h>
#include <shatter/plugin/geometry/JointBoxes.h>

#include <algorithm>

namespace shatter {

std::vector<int> fragmentsTouchingBox(const std::vector<geometry::PhysicalMesh>& fragments,
                                      const geometry::JointBox& box, double tolerance) {
    const geometry::ConvexPolyhedron probe = geometry::boxPolyhedron({box.pose, box.halfExtents});
    const geometry::Aabb reach = probe.bounds().inflated(tolerance);
    std::vector<int> out;
    for (int k = 0; k < int(fragments.size()); ++k) {
        const auto& primitives = fragments[k].primitives;
        const bool touches = std::any_of(primitives.begin(), primitives.end(), [&](const auto& p) {
            return p.bounds().overlaps(reach) && geometry::withinTolerance(p, probe, tolerance);
        });
        if (touches) out.push_back(k);
    }
    return out;
}

} // namespace shatter
