#pragma once
// Anchoring any shape: the tets held fixed are those whose centroid lies in a region, a
// half-space n·x <= d or an axis-aligned box, of the mesh's own coordinates or of the world's
// (where the body is created), so a statue on its feet or a column on a bevelled plinth can be
// anchored as well as a wall on a flat face.
#include <shatter/plugin/lattice/TetMesh.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>
#include <vector>

namespace shatter::lattice {

struct AnchorRegion {
    enum class Kind { HalfSpace, Box };
    enum class Frame { Mesh, World }; // whose coordinates the region is given in
    Kind kind = Kind::HalfSpace;
    Frame frame = Frame::Mesh;
    Eigen::Vector3d normal = Eigen::Vector3d::UnitY(); // half-space: any length but zero
    double offset = 0.0;                               // half-space: n·x <= offset, n normalised (m)
    Eigen::Vector3d lo = Eigen::Vector3d::Zero(), hi = Eigen::Vector3d::Zero(); // box corners (m)

    static AnchorRegion halfSpace(const Eigen::Vector3d& normal, double offset);
    static AnchorRegion box(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi);
    // The tets whose centroid lies at y <= height.
    static AnchorRegion below(double height) { return halfSpace(Eigen::Vector3d::UnitY(), height); }
    // The same region in world coordinates.
    AnchorRegion inWorld() const {
        AnchorRegion r = *this;
        r.frame = Frame::World;
        return r;
    }

    // Boundaries count as inside.
    bool contains(const Eigen::Vector3d& point) const;
    // In words, for messages: "n·x <= d with n = (0, 1, 0), d = 0.1" or "box (x0, y0, z0)-(x1, y1, z1)".
    std::string describe() const;
};

// The tets whose centroid lies in the region, in increasing order. `meshToWorld` places the
// mesh in the world (the body's pose at creation); only a World region uses it.
std::vector<int> tetsInRegion(const TetMesh& mesh, const AnchorRegion& region,
                              const Eigen::Isometry3d& meshToWorld = Eigen::Isometry3d::Identity());

// As tetsInRegion, but a region that holds no tet throws shatter::InputError naming the body:
// "body 'wall': the anchor region ... (world coordinates) holds no tet".
std::vector<int> anchoredTets(const TetMesh& mesh, const AnchorRegion& region, const std::string& body,
                              const Eigen::Isometry3d& meshToWorld = Eigen::Isometry3d::Identity());

} // namespace shatter::lattice
