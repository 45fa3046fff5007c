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

void shapeOfPrimitive(const geometry::ConvexPolyhedron& primitive, Solid& out) {
    out.positions = primitive.vertices();
    out.ids = primitive.globalIds();
    // The face list's flat indices at once, then the starts: a face at a time it was an insert
    // and two push_backs per face.
    const geometry::FaceList& faces = primitive.faces();
    out.faceVertices = faces.indices();
    const size_t count = faces.size();
    out.faceStart.resize(count + 1);
    out.faceStart[0] = 0;
    for (size_t f = 0; f < count; ++f) out.faceStart[f + 1] = out.faceStart[f] + int(faces[f].size());
    out.kinds.assign(count, FaceKind::Hidden);
}

void solidOfPrimitive(const geometry::ConvexPolyhedron& primitive, int visualVertexCount, Solid& out) {
    shapeOfPrimitive(primitive, out);
    for (size_t f = 0; f < out.kinds.size(); ++f) out.kinds[f] = kindOfFace(primitive, int(f), visualVertexCount);
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
    // Sized once, then written through a pointer: a push_back per face checked the capacity
    // and reloaded the vector's members each time.
    const size_t faces = size_t(solid.faceCount()), at = faceStart_.size();
    faceStart_.resize(at + faces);
    int* start = faceStart_.data() + at;
    const int* from = solid.faceStart.data() + 1;
    for (size_t f = 0; f < faces; ++f) start[f] = base + from[f];
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
