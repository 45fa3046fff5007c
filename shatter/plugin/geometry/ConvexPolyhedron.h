#pragma once
// A convex polyhedron primitive of the physical mesh (source 000 §3.1).
#include <shatter/plugin/geometry/Aabb.h>
#include <shatter/plugin/geometry/FaceList.h>
#include <shatter/plugin/common/InputError.h>
#include <shatter/plugin/geometry/MassProperties.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <memory>
#include <span>
#include <vector>

namespace shatter::geometry {

// Plane n·x = d with unit outward normal n.
struct Plane {
    Eigen::Vector3d normal;
    double offset;
    double signedDistance(const Eigen::Vector3d& p) const { return normal.dot(p) - offset; }
};

class ConvexPolyhedron {
public:
    // Faces are polygons of vertex indices, counter-clockwise seen from outside.
    // globalIds[i] is the global vertex id of vertex i (source 000 §3.4); vertices with
    // equal ids are welded in the visual mesh. Throws shatter::InputError when the
    // polyhedron is not a closed convex solid of positive volume; `what` names it.
    static ConvexPolyhedron create(std::vector<Eigen::Vector3d> vertices, std::vector<std::vector<int>> faces,
                                   std::vector<int> globalIds, const std::string& what = "polyhedron");
    // Same without the checks, for solids made by clipping a valid one with planes (fracture):
    // the caller guarantees closure and orientation; faces may be planar only within the
    // clipper's snap tolerance. Skips create()'s O(edges·log) closure map on a hot path.
    static ConvexPolyhedron createTrusted(std::vector<Eigen::Vector3d> vertices, FaceList faces,
                                          std::vector<int> globalIds);
    // A clipper's solid (trusted as above), its faces in one flat list: face f is
    // faceVertices[faceStart[f] .. faceStart[f + 1]). A face whose Newell normal is no longer
    // than 1e-12 × the squared diagonal of the bounds (collinear vertices, left where a cut
    // passed through collinear vertices) is left out: it adds nothing to the mass and its plane
    // would be noise for a separating-axis test. The kept faces' planes, bounds and mass
    // properties are createTrusted's of the kept faces bit for bit, in one pass that computes
    // each face's normal once (for the test and the plane).
    static ConvexPolyhedron createTrustedDroppingFlatFaces(std::vector<Eigen::Vector3d> vertices,
                                                          std::span<const int> faceStart,
                                                          std::span<const int> faceVertices,
                                                          std::vector<int> globalIds);

    const std::vector<Eigen::Vector3d>& vertices() const { return vertices_; }
    const FaceList& faces() const { return faces_ ? *faces_ : noFaces(); }
    const std::vector<Plane>& planes() const { return planes_; }
    const std::vector<int>& globalIds() const { return globalIds_; }
    const Aabb& bounds() const { return bounds_; }
    double volume() const { return mass_.volume; }
    // The centre of mass (that of massProperties, without turning the inertia).
    const Eigen::Vector3d& centerOfMass() const { return mass_.centerOfMass; }
    // Mass properties for a density in kg/m³ (inertia about the centre of mass).
    MassProperties massProperties(double density) const;

    // Farthest vertex along dir.
    const Eigen::Vector3d& support(const Eigen::Vector3d& dir) const;
    // Largest plane distance: < 0 inside, 0 on the surface, > 0 outside (a lower bound
    // of the Euclidean distance outside).
    double signedDistance(const Eigen::Vector3d& p) const;

    // Same polyhedron with other global ids (one per vertex; geometry copied bit for bit,
    // nothing recomputed).
    ConvexPolyhedron withGlobalIds(std::vector<int> globalIds) const;
    // The same, in place (no copy of the geometry).
    void setGlobalIds(std::vector<int> globalIds);
    // The same, the ids copied into this one's own storage (same count): nothing is allocated
    // or freed. RemainderEdit's id swaps give ~1k carriers per 16k-shell break new ids; a new
    // vector each, and the old one freed, was ~1.0 M instructions of five breaks.
    void overwriteGlobalIds(std::span<const int> globalIds);

    // Same polyhedron moved rigidly (ids kept).
    ConvexPolyhedron transformed(const Eigen::Isometry3d& t) const;
    // In place: this becomes `rest` moved rigidly by t. This must have rest's layout (a copy
    // of rest, moved before); then nothing is allocated and planes, bounds and mass
    // properties are moved, not recomputed (what a soft body's shape does every step). The
    // inertia is turned only when massProperties asks for it, by the same arithmetic (same
    // bits): a soft body's shape moves every primitive every step and rarely reads it.
    void moveTo(const ConvexPolyhedron& rest, const Eigen::Isometry3d& t);
    // This becomes from.moved(t), bit for bit, in this one's storage (its vectors keep their
    // room): faces and ids taken from `from`, the rest moved as moveTo does.
    void assignMoved(const ConvexPolyhedron& from, const Eigen::Isometry3d& t);
    // A new polyhedron: this moved by t as moveTo moves it (the same bits), the moved vertices
    // and planes written once (a copy then moveTo would copy them only to overwrite them).
    ConvexPolyhedron moved(const Eigen::Isometry3d& t) const;

private:
    // The polyhedron of these vertices and faces with its derived data (the create functions'
    // common part).
    static ConvexPolyhedron assemble(std::vector<Eigen::Vector3d> vertices, FaceList faces,
                                     std::vector<int> globalIds);
    void computeDerived();
    // The plane of a face from its Newell normal n and n's length.
    Plane planeOf(std::span<const int> face, const Eigen::Vector3d& n, double length) const;

    Eigen::Matrix3d turnedInertia() const; // mass_.inertia, turned by inertiaTurn_ if set
    static const FaceList& noFaces(); // a default-constructed polyhedron's

    std::vector<Eigen::Vector3d> vertices_;
    // Shared, never edited: a copy, a moved() or a withGlobalIds() shares its faces with the
    // original instead of copying them (two allocations and frees saved per copy; a 64-cell
    // break of the 16k shell copies ~2,300 primitives per event: see FaceList.h).
    std::shared_ptr<const FaceList> faces_;
    std::vector<Plane> planes_;
    std::vector<int> globalIds_;
    Aabb bounds_;
    MassProperties mass_; // at unit density; its inertia not yet turned when `turned_`
    Eigen::Matrix3d inertiaTurn_; // the turn of the last moveTo, when `turned_`
    bool turned_ = false;
};

// Newell normal of a polygon (not normalised; its length is twice the area).
Eigen::Vector3d newellNormal(const std::vector<Eigen::Vector3d>& points, std::span<const int> polygon);

} // namespace shatter::geometry
