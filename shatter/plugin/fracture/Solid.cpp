#include <shatter/plugin/fracture/Solid.h>

namespace shatter::fracture {

void Solid::clear() {
    positions.clear();
    ids.clear();
    faceStart.assign(1, 0);
    faceVertices.clear();
    kinds.clear();
}

FaceKind kindOfFace(const geometry::ConvexPolyhedron& primitive, int face, int visualVertexCount) {
    for (int v : primitive.faces()[size_t(face)])
        if (primitive.globalIds()[size_t(v)] >= visualVertexCount) return FaceKind::Hidden;
    return FaceKind::Visual;
}

void solidOfPrimitive(const geometry::ConvexPolyhedron& primitive, int visualVertexCount, Solid& out) {
    out.clear();
    out.positions = primitive.vertices();
    out.ids = primitive.globalIds();
    for (size_t f = 0; f < primitive.faces().size(); ++f) {
        const std::span<const int> face = primitive.faces()[f];
        out.faceVertices.insert(out.faceVertices.end(), face.begin(), face.end());
        out.addFace(kindOfFace(primitive, int(f), visualVertexCount));
    }
}

geometry::ConvexPolyhedron takePolyhedron(Solid& solid) {
    std::vector<Eigen::Vector3d> positions = std::move(solid.positions);
    // A face whose vertices are (nearly) collinear, left where a cut passed through collinear
    // vertices, has no normal of its own: it adds nothing to the mass and its plane would be
    // noise for a separating-axis test, so the polyhedron leaves it out (the visual mesh,
    // built from the solid, keeps it and stays closed).
    geometry::Aabb box;
    for (const auto& p : positions) box.extend(p);
    const double minimumNormal = 1e-12 * box.diagonal() * box.diagonal();
    geometry::FaceList faces;
    std::vector<Eigen::Vector3d> normals; // the kept faces' (the polyhedron's planes need them too)
    faces.reserve(size_t(solid.faceCount()), solid.faceVertices.size());
    normals.reserve(size_t(solid.faceCount()));
    for (int f = 0; f < solid.faceCount(); ++f) {
        const std::span<const int> face(solid.faceVertices.data() + solid.faceStart[size_t(f)],
                                        size_t(solid.faceStart[size_t(f) + 1] - solid.faceStart[size_t(f)]));
        const Eigen::Vector3d n = geometry::newellNormal(positions, face);
        if (n.norm() <= minimumNormal) continue;
        faces.add(face);
        normals.push_back(n);
    }
    return geometry::ConvexPolyhedron::createTrusted(std::move(positions), std::move(faces), solid.ids, normals);
}

} // namespace shatter::fracture
