#pragma once
// Bodies of cubes and their partitions into fragments, made by hand (no cutting): the Bullet
// side of fracture tested on its own.
#include <shatter/bullet_ext/Convert.h>
#include <shatter/plugin/geometry/Connectivity.h>
#include <shatter/plugin/geometry/PhysicalMesh.h>

#include <btBulletDynamicsCommon.h>

#include <map>
#include <string>
#include <vector>

namespace shatter::test {

// nx × ny × nz cubes of edge `size` (m) touching face to face, corner at `corner`, one
// primitive per cube, density 1000 kg/m³. Cube (i, j, k) is primitive i + nx (j + ny k).
inline geometry::PhysicalMesh cubeBlock(const std::string& name, int nx, int ny, int nz, double size,
                                        const Eigen::Vector3d& corner = Eigen::Vector3d::Zero()) {
    geometry::PhysicalMesh mesh;
    mesh.name = name;
    mesh.density = 1000.0;
    mesh.contactTolerance = 1e-5;
    mesh.thickness = size;
    const std::vector<std::vector<int>> faces = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                                 {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (int k = 0; k < nz; ++k)
        for (int j = 0; j < ny; ++j)
            for (int i = 0; i < nx; ++i) {
                const Eigen::Vector3d lo = corner + Eigen::Vector3d(i, j, k) * size;
                std::vector<Eigen::Vector3d> v;
                std::vector<int> ids;
                for (int c = 0; c < 8; ++c) {
                    v.push_back(lo + size * Eigen::Vector3d(c & 1, (c >> 1) & 1, (c >> 2) & 1));
                    ids.push_back(int(mesh.visual.positions.size()));
                    mesh.visual.positions.push_back(v.back());
                }
                for (auto f : faces) {
                    for (int& x : f) x = ids[x];
                    mesh.visual.faces.push_back(f);
                }
                mesh.primitives.push_back(geometry::ConvexPolyhedron::create(v, faces, ids, "cube"));
                mesh.sourceFace.push_back(-1);
                mesh.mass += mesh.primitives.back().massProperties(mesh.density);
            }
    mesh.globalIdCount = int(mesh.visual.positions.size());
    mesh.connections = geometry::touchingPairs(mesh.primitives, mesh.contactTolerance);
    return mesh;
}

// The fragments of `mesh` whose primitives `group` gives (one group number per primitive,
// 0..groups-1): each with its primitives, their visual faces and connections, and the exact
// mass of its pieces.
inline std::vector<geometry::PhysicalMesh> partition(const geometry::PhysicalMesh& mesh, const std::vector<int>& group) {
    int groups = 0;
    for (int g : group) groups = std::max(groups, g + 1);
    std::vector<geometry::PhysicalMesh> out(static_cast<size_t>(groups));
    std::vector<int> index(mesh.primitives.size());
    for (auto& f : out) {
        f.name = mesh.name;
        f.density = mesh.density;
        f.contactTolerance = mesh.contactTolerance;
        f.thickness = mesh.thickness;
        f.globalIdCount = mesh.globalIdCount;
        f.visual.positions = mesh.visual.positions;
    }
    for (size_t p = 0; p < mesh.primitives.size(); ++p) {
        auto& f = out[size_t(group[p])];
        index[p] = int(f.primitives.size());
        f.primitives.push_back(mesh.primitives[p]);
        f.sourceFace.push_back(-1);
        f.mass += mesh.primitives[p].massProperties(mesh.density);
        for (int face = 0; face < 6; ++face) f.visual.faces.push_back(mesh.visual.faces[6 * p + size_t(face)]);
    }
    for (const auto& [a, b] : mesh.connections)
        if (group[a] == group[b]) out[size_t(group[a])].connections.emplace_back(index[a], index[b]);
    return out;
}

inline double kineticEnergy(const btRigidBody& b) {
    if (b.getInvMass() == 0) return 0.0;
    const btVector3 w = b.getAngularVelocity();
    const btMatrix3x3 inertia = b.getInvInertiaTensorWorld().inverse();
    return 0.5 / double(b.getInvMass()) * double(b.getLinearVelocity().length2()) + 0.5 * double(w.dot(inertia * w));
}

// Mass, momentum and angular momentum (about the origin) of Bullet bodies, as Bullet holds them.
struct BulletMomenta {
    double mass = 0.0;
    Eigen::Vector3d linear = Eigen::Vector3d::Zero(), angular = Eigen::Vector3d::Zero();
    void add(const btRigidBody& b) {
        if (b.getInvMass() == 0) return;
        const double m = 1.0 / double(b.getInvMass());
        const Eigen::Vector3d p = m * toEigen(b.getLinearVelocity());
        mass += m;
        linear += p;
        angular += toEigen(b.getCenterOfMassPosition()).cross(p) +
                   toEigen(b.getInvInertiaTensorWorld().inverse() * b.getAngularVelocity());
    }
};

} // namespace shatter::test
