#include <shatter/bullet_ext/lattice/BuriedTets.h>

#include <shatter/bullet_ext/VisualBody.h>
#include <shatter/bullet_ext/shape/GroupShape.h>

namespace shatter {

std::vector<char> buriedPrimitives(const geometry::PhysicalMesh& mesh) {
    std::vector<char> onSurface(size_t(mesh.globalIdCount), 0);
    for (const auto& face : mesh.visual.faces)
        for (int v : face) onSurface[size_t(v)] = 1;
    std::vector<char> buried(mesh.primitives.size(), 1);
    for (size_t i = 0; i < mesh.primitives.size(); ++i)
        for (int id : mesh.primitives[i].globalIds())
            if (onSurface[size_t(id)]) {
                buried[i] = 0;
                break;
            }
    return buried;
}

void markBuriedTets(VisualBody& body) {
    if (auto* group = dynamic_cast<GroupShape*>(body.rigidBody().getCollisionShape()))
        group->setBuried(buriedPrimitives(body.physicalMesh()));
}

} // namespace shatter
