#include <shatter/plugin/geometry/ConvexPolyhedron.h>

#include <shatter/plugin/common/InputError.h>

#include <cmath>
#include <map>
#include <sstream>
#include <stdexcept>

namespace shatter::geometry {

Eigen::Vector3d newellNormal(const std::vector<Eigen::Vector3d>& points, std::span<const int> polygon) {
    // Relative to the first vertex: absolute coordinates far from the origin would cancel.
    Eigen::Vector3d n = Eigen::Vector3d::Zero();
    if (polygon.empty()) return n;
    const Eigen::Vector3d& origin = points[polygon[0]];
    // Each edge's end is the next edge's start: one difference per vertex (the same values).
    Eigen::Vector3d a = points[polygon[0]] - origin;
    for (size_t i = 0; i < polygon.size(); ++i) {
        const Eigen::Vector3d b = points[polygon[i + 1 < polygon.size() ? i + 1 : 0]] - origin; // no division
        n += a.cross(b);
        a = b;
    }
    return n;
}

namespace {

// newellNormal of a polygon of finite points, the same bits, inlined where a cut piece's faces
// are measured (out of line, its call and the vector's reloads were a third of its ~180
// instructions a face). Its first and last terms are left out: each is a cross product with
// the first vertex minus itself, a zero vector, so its components are +0 or -0, and adding
// those to a sum that starts at +0 (and so is never -0, rounding to nearest) changes no bit.
[[gnu::always_inline]] inline Eigen::Vector3d finiteNewellNormal(const Eigen::Vector3d* points,
                                                                 std::span<const int> polygon) {
    Eigen::Vector3d n = Eigen::Vector3d::Zero();
    if (polygon.size() < 3) return n; // every term has the zero vector
    const Eigen::Vector3d& origin = points[polygon[0]];
    Eigen::Vector3d a = points[polygon[1]] - origin;
    for (size_t i = 2; i < polygon.size(); ++i) {
        const Eigen::Vector3d b = points[polygon[i]] - origin;
        n += a.cross(b);
        a = b;
    }
    return n;
}

// The plane of a face with Newell normal n (|n| = length): the unit normal and its mean offset
// over the face's vertices. Inline, for createTrustedDroppingFlatFaces' loop (see there).
[[gnu::always_inline]] inline Plane planeThrough(const Eigen::Vector3d* points, std::span<const int> face,
                                                 const Eigen::Vector3d& n, double length) {
    const Eigen::Vector3d unit = length > 0.0 ? Eigen::Vector3d(n / length) : Eigen::Vector3d::UnitZ();
    double d = 0.0;
    for (int i : face) d += unit.dot(points[i]);
    return {unit, d / double(face.size())};
}

[[noreturn]] void fail(const std::string& what, const std::string& problem) {
    throw InputError(what + ": " + problem);
}

void checkIndicesAndClosure(const std::vector<Eigen::Vector3d>& vertices, const std::vector<std::vector<int>>& faces,
                            const std::vector<int>& ids, const std::string& what) {
    if (vertices.size() < 4) fail(what, "needs at least 4 vertices, has " + std::to_string(vertices.size()));
    if (faces.size() < 4) fail(what, "needs at least 4 faces, has " + std::to_string(faces.size()));
    if (ids.size() != vertices.size()) fail(what, "has " + std::to_string(ids.size()) + " global ids for " +
                                                      std::to_string(vertices.size()) + " vertices");
    for (const auto& v : vertices)
        if (!v.allFinite()) fail(what, "has a non-finite vertex coordinate");
    // Closed and consistently oriented: every directed edge appears once and its reverse once.
    std::map<std::pair<int, int>, int> directed;
    for (size_t f = 0; f < faces.size(); ++f) {
        if (faces[f].size() < 3) fail(what, "face " + std::to_string(f) + " has fewer than 3 vertices");
        for (size_t k = 0; k < faces[f].size(); ++k) {
            const int a = faces[f][k];
            const int b = faces[f][(k + 1) % faces[f].size()];
            if (a < 0 || b < 0 || a >= int(vertices.size()) || b >= int(vertices.size()))
                fail(what, "face " + std::to_string(f) + " has a vertex index out of range");
            if (++directed[{a, b}] > 1) fail(what, "edge used twice in the same direction (inconsistent orientation)");
        }
    }
    for (const auto& [edge, count] : directed)
        if (!directed.count({edge.second, edge.first})) fail(what, "is not closed (an edge has only one face)");
}

} // namespace

ConvexPolyhedron ConvexPolyhedron::create(std::vector<Eigen::Vector3d> vertices, std::vector<std::vector<int>> faces,
                                          std::vector<int> globalIds, const std::string& what) {
    checkIndicesAndClosure(vertices, faces, globalIds, what);
    ConvexPolyhedron p = assemble(std::move(vertices), FaceList(faces), std::move(globalIds));
    if (!(p.mass_.volume > 0.0)) fail(what, "has non-positive volume (inverted or flat)");
    // Convexity: every vertex on or behind every face plane, within a tolerance relative
    // to the size (round-off of coplanar input, collinear polygon vertices).
    const double tol = 1e-9 * std::max(1.0, p.bounds_.diagonal()) + 1e-7 * p.bounds_.diagonal();
    for (size_t f = 0; f < p.planes_.size(); ++f)
        for (const auto& v : p.vertices_)
            if (p.planes_[f].signedDistance(v) > tol) {
                std::ostringstream msg;
                msg << "is not convex (a vertex lies " << p.planes_[f].signedDistance(v) << " m outside face " << f << ")";
                fail(what, msg.str());
            }
    return p;
}

ConvexPolyhedron ConvexPolyhedron::createTrusted(std::vector<Eigen::Vector3d> vertices, FaceList faces,
                                                 std::vector<int> globalIds) {
    return assemble(std::move(vertices), std::move(faces), std::move(globalIds));
}

ConvexPolyhedron ConvexPolyhedron::createTrustedDroppingFlatFaces(std::vector<Eigen::Vector3d> vertices,
                                                                  std::span<const int> faceStart,
                                                                  std::span<const int> faceVertices,
                                                                  std::vector<int> globalIds) {
    ConvexPolyhedron p;
    p.vertices_ = std::move(vertices);
    p.globalIds_ = std::move(globalIds);
    // Through locals and pointers, the normal and plane arithmetic inlined: stores to the box,
    // the planes or the faces may alias the vectors' members, which were then reloaded per
    // vertex (cut16: the function 28.8 -> 26.0 M instructions in five 16k-shell breaks).
    const Eigen::Vector3d* points = p.vertices_.data();
    const size_t vertexCount = p.vertices_.size();
    Aabb box;
    for (size_t v = 0; v < vertexCount; ++v) box.extend(points[v]);
    p.bounds_ = box;
    const double minimumNormal = 1e-12 * box.diagonal() * box.diagonal();
    const size_t faceCount = faceStart.empty() ? 0 : faceStart.size() - 1;
    // The faces are copied at once when none is dropped (almost always): the list is built face
    // by face only from the first dropped face on, after a copy of those before it (same list).
    FaceList faces;
    bool adding = faceStart.empty() || faceStart[0] != 0; // (not a clipper's list: face by face)
    if (adding) faces.reserve(faceCount, faceVertices.size());
    p.planes_.resize(faceCount);
    Plane* plane = p.planes_.data();
    size_t kept = 0;
    for (size_t f = 0; f < faceCount; ++f) {
        const std::span<const int> face = faceVertices.subspan(size_t(faceStart[f]), size_t(faceStart[f + 1] - faceStart[f]));
        const Eigen::Vector3d n = finiteNewellNormal(points, face); // (a clipper's vertices are finite)
        const double length = n.norm();
        if (length <= minimumNormal) {
            if (!adding) {
                faces = FaceList::fromFlat(faceStart.first(f + 1), faceVertices.first(size_t(faceStart[f])));
                faces.reserve(faceCount, faceVertices.size());
                adding = true;
            }
            continue;
        }
        if (adding) faces.add(face);
        plane[kept++] = planeThrough(points, face, n, length);
    }
    if (!adding) faces = FaceList::fromFlat(faceStart, faceVertices.first(size_t(faceStart[faceCount])));
    p.planes_.resize(kept);
    p.mass_ = polyhedronMassProperties(p.vertices_, faces, 1.0);
    p.faces_ = std::make_shared<const FaceList>(std::move(faces));
    return p;
}

const FaceList& ConvexPolyhedron::noFaces() {
    static const FaceList none;
    return none;
}

ConvexPolyhedron ConvexPolyhedron::assemble(std::vector<Eigen::Vector3d> vertices, FaceList faces,
                                            std::vector<int> globalIds) {
    ConvexPolyhedron p;
    p.vertices_ = std::move(vertices);
    p.faces_ = std::make_shared<const FaceList>(std::move(faces));
    p.globalIds_ = std::move(globalIds);
    p.computeDerived();
    return p;
}

Plane ConvexPolyhedron::planeOf(std::span<const int> face, const Eigen::Vector3d& n, double length) const {
    return planeThrough(vertices_.data(), face, n, length);
}

void ConvexPolyhedron::computeDerived() {
    bounds_ = Aabb{};
    for (const auto& v : vertices_) bounds_.extend(v);
    planes_.clear();
    const FaceList& faceList = faces();
    planes_.reserve(faceList.size());
    for (const std::span<const int> face : faceList) {
        const Eigen::Vector3d n = newellNormal(vertices_, face);
        planes_.push_back(planeOf(face, n, n.norm()));
    }
    mass_ = polyhedronMassProperties(vertices_, faceList, 1.0);
    turned_ = false;
}

Eigen::Matrix3d ConvexPolyhedron::turnedInertia() const {
    if (!turned_) return mass_.inertia;
    return inertiaTurn_ * mass_.inertia * inertiaTurn_.transpose();
}

MassProperties ConvexPolyhedron::massProperties(double density) const {
    MassProperties m = mass_;
    m.inertia = turnedInertia();
    m.mass *= density;
    m.inertia *= density;
    return m;
}

const Eigen::Vector3d& ConvexPolyhedron::support(const Eigen::Vector3d& dir) const {
    size_t best = 0;
    double bestDot = vertices_[0].dot(dir);
    for (size_t i = 1; i < vertices_.size(); ++i) {
        const double d = vertices_[i].dot(dir);
        if (d > bestDot) {
            bestDot = d;
            best = i;
        }
    }
    return vertices_[best];
}

double ConvexPolyhedron::signedDistance(const Eigen::Vector3d& p) const {
    double d = -std::numeric_limits<double>::infinity();
    for (const auto& plane : planes_) d = std::max(d, plane.signedDistance(p));
    return d;
}

ConvexPolyhedron ConvexPolyhedron::withGlobalIds(std::vector<int> globalIds) const {
    // Every member but the ids copied (a copy of the whole would copy the ids only to free them).
    ConvexPolyhedron p;
    p.vertices_ = vertices_;
    p.faces_ = faces_;
    p.planes_ = planes_;
    p.bounds_ = bounds_;
    p.mass_ = mass_;
    p.inertiaTurn_ = inertiaTurn_;
    p.turned_ = turned_;
    p.setGlobalIds(std::move(globalIds));
    return p;
}

void ConvexPolyhedron::setGlobalIds(std::vector<int> globalIds) {
    if (globalIds.size() != vertices_.size())
        throw std::invalid_argument("ConvexPolyhedron::setGlobalIds: " + std::to_string(globalIds.size()) +
                                    " ids for " + std::to_string(vertices_.size()) + " vertices");
    globalIds_ = std::move(globalIds);
}

void ConvexPolyhedron::overwriteGlobalIds(std::span<const int> globalIds) {
    if (globalIds.size() != globalIds_.size())
        throw std::invalid_argument("ConvexPolyhedron::overwriteGlobalIds: " + std::to_string(globalIds.size()) +
                                    " ids for " + std::to_string(globalIds_.size()) + " vertices");
    std::copy(globalIds.begin(), globalIds.end(), globalIds_.begin());
}

ConvexPolyhedron ConvexPolyhedron::transformed(const Eigen::Isometry3d& t) const {
    ConvexPolyhedron p = *this;
    for (auto& v : p.vertices_) v = t * v;
    p.computeDerived();
    return p;
}

void ConvexPolyhedron::moveTo(const ConvexPolyhedron& rest, const Eigen::Isometry3d& t) {
    const Eigen::Matrix3d& r = t.linear();
    // Counts and pointers in locals: a store to a vertex or plane might alias the vectors'
    // own pointers, so the compiler would reload them and recount the size each pass (5 of a
    // vertex's 45 instructions). The box too: in bounds_ it would be written and reloaded per
    // vertex (a store-forwarding stall).
    const size_t vertexCount = rest.vertices_.size();
    vertices_.resize(vertexCount);
    const Eigen::Vector3d* restVertex = rest.vertices_.data();
    Eigen::Vector3d* vertex = vertices_.data();
    Aabb box;
    for (size_t k = 0; k < vertexCount; ++k) {
        const Eigen::Vector3d v = t * restVertex[k];
        vertex[k] = v;
        box.extend(v);
    }
    bounds_ = box;
    const size_t planeCount = rest.planes_.size();
    planes_.resize(planeCount);
    const Plane* restPlane = rest.planes_.data();
    Plane* plane = planes_.data();
    const Eigen::Vector3d shift = t.translation();
    for (size_t f = 0; f < planeCount; ++f) {
        const Eigen::Vector3d n = r * restPlane[f].normal;
        const double offset = restPlane[f].offset + n.dot(shift);
        plane[f].normal = n;
        plane[f].offset = offset;
    }
    mass_ = rest.mass_;
    mass_.centerOfMass = t * rest.mass_.centerOfMass;
    if (rest.turned_) mass_.inertia = rest.turnedInertia(); // a moved rest: turn as the eager moves did
    inertiaTurn_ = r;
    turned_ = true;
}

ConvexPolyhedron ConvexPolyhedron::moved(const Eigen::Isometry3d& t) const {
    ConvexPolyhedron p;
    p.assignMoved(*this, t);
    return p;
}

void ConvexPolyhedron::assignMoved(const ConvexPolyhedron& from, const Eigen::Isometry3d& t) {
    faces_ = from.faces_;
    globalIds_ = from.globalIds_;
    moveTo(from, t); // sizes the vertices and planes, then writes them
}

} // namespace shatter::geometry
