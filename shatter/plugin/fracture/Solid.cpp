#include <shatter/plugin/fracture/Solid.h>

#include <algorithm>

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

template <typename T>
T* CutFaceStore::Blocks<T>::take(size_t n) {
    if (n > left_) {
        const size_t size = std::max(n, kBlock);
        blocks_.emplace_back(new T[size]); // left uninitialised: every value is written before it is read
        next_ = blocks_.back().get();
        left_ = size;
    }
    T* at = next_;
    next_ += n;
    left_ -= n;
    return at;
}

int CutFaceStore::add(const Solid& solid) {
    // A piece's faceStart is its solid's, from 0: its faceVertices start where it says.
    const size_t faces = size_t(solid.faceCount()), vertices = solid.faceVertices.size(), ids = solid.ids.size();
    int* ints = ints_.take(faces + 1 + vertices + ids);
    std::copy_n(solid.faceStart.data(), faces + 1, ints);
    std::copy_n(solid.faceVertices.data(), vertices, ints + faces + 1);
    std::copy_n(solid.ids.data(), ids, ints + faces + 1 + vertices);
    FaceKind* kinds = kinds_.take(faces);
    std::copy_n(solid.kinds.data(), faces, kinds);
    // Room for a 64-cell break of the 16k shell (~1,100 pieces) at once.
    if (pieces_.empty()) pieces_.reserve(1024);
    pieces_.push_back({ints, kinds, int(faces), int(vertices), int(ids)});
    return int(pieces_.size()) - 1;
}

CutFaces CutFaceStore::operator[](int piece) const {
    const Piece& p = pieces_[size_t(piece)];
    const size_t faces = size_t(p.faces), vertices = size_t(p.vertices);
    return {std::span<const int>(p.ints, faces + 1), std::span<const int>(p.ints + faces + 1, vertices),
            std::span<const FaceKind>(p.kinds, faces), std::span<const int>(p.ints + faces + 1 + vertices, size_t(p.ids))};
}

} // namespace shatter::fracture
