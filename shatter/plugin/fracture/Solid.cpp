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
    // A face whose vertices are (nearly) collinear, left where a cut passed through collinear
    // vertices, has no normal of its own: the polyhedron leaves it out (the visual mesh, built
    // from the solid, keeps it and stays closed).
    return geometry::ConvexPolyhedron::createTrustedDroppingFlatFaces(std::move(solid.positions), solid.faceStart,
                                                                      solid.faceVertices, solid.ids);
}

} // namespace shatter::fracture
