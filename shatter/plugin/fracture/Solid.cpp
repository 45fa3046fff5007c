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
        const auto& face = primitive.faces()[f];
        out.faceVertices.insert(out.faceVertices.end(), face.begin(), face.end());
        out.addFace(kindOfFace(primitive, int(f), visualVertexCount));
    }
}

geometry::ConvexPolyhedron polyhedronOfSolid(const Solid& solid) {
    std::vector<std::vector<int>> faces(size_t(solid.faceCount()));
    for (int f = 0; f < solid.faceCount(); ++f)
        faces[size_t(f)].assign(solid.faceVertices.begin() + solid.faceStart[size_t(f)],
                                solid.faceVertices.begin() + solid.faceStart[size_t(f) + 1]);
    return geometry::ConvexPolyhedron::createTrusted(solid.positions, std::move(faces), solid.ids);
}

} // namespace shatter::fracture
