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

geometry::ConvexPolyhedron polyhedronOf(const Solid& solid) {
    // A face whose vertices are (nearly) collinear, left where a cut passed through collinear
    // vertices, has no normal of its own: the polyhedron leaves it out (the visual mesh, built
    // from the solid, keeps it and stays closed).
    return geometry::ConvexPolyhedron::createTrustedDroppingFlatFaces(solid.positions, solid.faceStart,
                                                                      solid.faceVertices, solid.ids);
}

int CutFaceStore::add(const Solid& solid) {
    const int base = int(faceVertices_.size());
    for (int f = 1; f <= solid.faceCount(); ++f) faceStart_.push_back(base + solid.faceStart[size_t(f)]);
    faceVertices_.insert(faceVertices_.end(), solid.faceVertices.begin(), solid.faceVertices.end());
    kinds_.insert(kinds_.end(), solid.kinds.begin(), solid.kinds.end());
    ids_.insert(ids_.end(), solid.ids.begin(), solid.ids.end());
    firstFace_.push_back(int(kinds_.size()));
    firstId_.push_back(int(ids_.size()));
    return int(firstFace_.size()) - 2;
}

CutFaces CutFaceStore::operator[](int piece) const {
    const size_t face = size_t(firstFace_[size_t(piece)]), faces = size_t(firstFace_[size_t(piece) + 1]) - face;
    const size_t id = size_t(firstId_[size_t(piece)]), ids = size_t(firstId_[size_t(piece) + 1]) - id;
    return {std::span<const int>(faceStart_).subspan(face, faces + 1), faceVertices_,
            std::span<const FaceKind>(kinds_).subspan(face, faces), std::span<const int>(ids_).subspan(id, ids)};
}

} // namespace shatter::fracture
