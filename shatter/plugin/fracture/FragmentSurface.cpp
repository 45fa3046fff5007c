#include <shatter/plugin/fracture/FragmentSurface.h>

#include <algorithm>
#include <cstdint>
#include <map>

namespace shatter::fracture {

namespace {

bool closedSurface(const geometry::VisualMesh& visual) {
    std::vector<std::uint64_t> edges;
    for (const auto& f : visual.faces)
        for (size_t k = 0; k < f.size(); ++k)
            edges.push_back(std::uint64_t(std::uint32_t(f[k])) << 32 | std::uint32_t(f[(k + 1) % f.size()]));
    if (edges.empty()) return false;
    std::sort(edges.begin(), edges.end());
    for (size_t i = 0; i < edges.size(); ++i) {
        if (i + 1 < edges.size() && edges[i + 1] == edges[i]) return false; // used twice the same way
        const std::uint64_t reverse = edges[i] >> 32 | edges[i] << 32;
        if (!std::binary_search(edges.begin(), edges.end(), reverse)) return false;
    }
    return true;
}

// The face's ids turned to start at the smallest one: equal keys, equal polygons.
std::vector<int> canonical(std::vector<int> face) {
    std::rotate(face.begin(), std::min_element(face.begin(), face.end()), face.end());
    return face;
}

} // namespace

FragmentSurface::FragmentSurface(const geometry::PhysicalMesh& body)
    : body_(body), visualCount_(int(body.visual.positions.size())), closed_(closedSurface(body.visual)),
      primitivesOfFace_(body.visual.faces.size(), 0), wholeCount_(body.visual.faces.size(), 0),
      emittedIn_(body.visual.faces.size(), -1) {
    for (int f : body.sourceFace)
        if (f >= 0) ++primitivesOfFace_[size_t(f)];
}

void FragmentSurface::emit(std::vector<int> face, bool crack, bool cancellable, FragmentFaces& out) {
    out.faces.push_back(std::move(face));
    out.crack.push_back(crack);
    cancellable_.push_back(cancellable);
}

FragmentFaces FragmentSurface::build(const std::vector<FragmentPart>& parts) {
    FragmentFaces out;
    cancellable_.clear();
    ++serial_;
    for (const auto& part : parts)
        if (!part.cut && body_.sourceFace[size_t(part.parent)] >= 0) ++wholeCount_[size_t(body_.sourceFace[size_t(part.parent)])];

    std::vector<int> ids;
    for (const auto& part : parts) {
        out.sourceFace.push_back(-1);
        if (part.cut) {
            const Solid& s = *part.cut;
            for (int f = 0; f < s.faceCount(); ++f) {
                if (s.kinds[size_t(f)] == FaceKind::Hidden && !closed_) continue;
                ids.clear();
                for (int k = s.faceStart[size_t(f)]; k < s.faceStart[size_t(f) + 1]; ++k)
                    ids.push_back(s.ids[size_t(s.faceVertices[size_t(k)])]);
                emit(ids, s.kinds[size_t(f)] == FaceKind::Crack, s.kinds[size_t(f)] != FaceKind::Visual, out);
            }
            continue;
        }
        const auto& primitive = body_.primitives[size_t(part.parent)];
        const int source = body_.sourceFace[size_t(part.parent)];
        const bool faceWhole = source >= 0 && wholeCount_[size_t(source)] == primitivesOfFace_[size_t(source)];
        if (faceWhole && emittedIn_[size_t(source)] != serial_) {
            emittedIn_[size_t(source)] = serial_;
            out.sourceFace.back() = int(out.faces.size());
            emit(body_.visual.faces[size_t(source)], false, false, out);
        }
        for (size_t f = 0; f < primitive.faces().size(); ++f) {
            const FaceKind kind = kindOfFace(primitive, int(f), visualCount_);
            if (kind == FaceKind::Visual ? faceWhole : (kind == FaceKind::Hidden && !closed_)) continue;
            ids.clear();
            for (int v : primitive.faces()[f]) ids.push_back(primitive.globalIds()[size_t(v)]);
            emit(ids, false, kind != FaceKind::Visual, out);
        }
    }
    for (const auto& part : parts)
        if (!part.cut && body_.sourceFace[size_t(part.parent)] >= 0) --wholeCount_[size_t(body_.sourceFace[size_t(part.parent)])];
    cancelBackToBack(out);
    return out;
}

void FragmentSurface::cancelBackToBack(FragmentFaces& out) {
    std::map<std::vector<int>, std::vector<int>> open; // canonical face → emitted faces not yet cancelled
    std::vector<char> gone(out.faces.size(), 0);
    for (size_t i = 0; i < out.faces.size(); ++i) {
        if (!cancellable_[i]) continue;
        std::vector<int> reversed(out.faces[i].rbegin(), out.faces[i].rend());
        auto it = open.find(canonical(std::move(reversed)));
        if (it != open.end() && !it->second.empty()) {
            gone[size_t(it->second.back())] = 1;
            gone[i] = 1;
            it->second.pop_back();
            continue;
        }
        open[canonical(out.faces[i])].push_back(int(i));
    }
    FragmentFaces kept;
    std::vector<int> newIndex(out.faces.size(), -1);
    for (size_t i = 0; i < out.faces.size(); ++i) {
        if (gone[i]) continue;
        newIndex[i] = int(kept.faces.size());
        kept.faces.push_back(std::move(out.faces[i]));
        kept.crack.push_back(out.crack[i]);
    }
    kept.sourceFace = out.sourceFace;
    for (int& f : kept.sourceFace)
        if (f >= 0) f = newIndex[size_t(f)];
    out = std::move(kept);
}

} // namespace shatter::fracture
