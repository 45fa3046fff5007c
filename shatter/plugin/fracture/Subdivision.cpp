#include <shatter/plugin/fracture/Subdivision.h>
#include <shatter/plugin/common/Stopwatch.h>

#include <shatter/plugin/geometry/Connectivity.h>

#include <algorithm>
#include <map>
#include <numeric>

namespace shatter::fracture {

namespace {

// One primitive of the subdivided body, in fracture-wide global ids (the body's ids for the
// vertices it had, new ones from body.globalIdCount up): the body's primitive, or a cut piece.
// A pointer, so that sorting the parts of a large body copies no polyhedron.
struct Part {
    int parent = 0;
    bool clipped = false;
    const geometry::ConvexPolyhedron* shape = nullptr;
};

class Assembler {
public:
    Assembler(const geometry::PhysicalMesh& body, const CutSettings& settings)
        : body_(body), tolerance_(settings.snapTolerance), visualCount_(int(body.visual.positions.size())) {}

    SubdivisionResult run(CutPieces cut) {
        collectParts(std::move(cut));
        buildSurface();
        renumberIds();
        repairTJunctions();
        SubdivisionResult result;
        result.primitivesCut = cut.primitivesCut;
        result.kept = kept_;
        geometry::PhysicalMesh& mesh = result.mesh;
        mesh.name = body_.name;
        mesh.thickness = body_.thickness;
        mesh.density = body_.density;
        mesh.contactTolerance = body_.contactTolerance;
        mesh.warnings = body_.warnings;
        mesh.visual.faces = std::move(faces_);
        if (std::find(crack_.begin(), crack_.end(), true) != crack_.end()) mesh.visual.crackFace = std::move(crack_);
        mesh.visual.positions = std::move(positions_);
        mesh.globalIdCount = idCount_;
        for (size_t i = 0; i < parts_.size(); ++i) {
            const Part& part = parts_[i];
            std::vector<int> ids;
            ids.reserve(part.shape->globalIds().size());
            for (int id : part.shape->globalIds()) ids.push_back(newId_[size_t(id)]);
            mesh.primitives.push_back(part.shape->withGlobalIds(std::move(ids)));
            mesh.mass += mesh.primitives.back().massProperties(body_.density);
            result.parents.push_back(part.parent);
            result.clipped.push_back(part.clipped);
        }
        mesh.sourceFace = std::move(sourceFace_);
        mesh.connections = connections();
        return result;
    }

private:
    // The uncut primitives in body order, then the pieces by body primitive (stable: a
    // primitive's pieces in the order the cut gave them); an uncut primitive is the body's own.
    void collectParts(CutPieces cut) {
        pieces_ = std::move(cut.shapes); // parts point into it
        size_t next = 0;
        for (size_t k = 0; k < cut.parents.size(); ++k) {
            const int parent = cut.parents[k];
            if (cut.clipped[k]) parts_.push_back({parent, true, &pieces_[next++]});
            else parts_.push_back({parent, false, &body_.primitives[size_t(parent)]});
        }
        // A primitive is either moved whole (one part) or cut (all its parts clipped).
        cut_.assign(body_.primitives.size(), false);
        for (const Part& p : parts_) cut_[size_t(p.parent)] = cut_[size_t(p.parent)] || p.clipped;
        std::stable_sort(parts_.begin(), parts_.end(), [&](const Part& a, const Part& b) {
            return cut_[size_t(a.parent)] != cut_[size_t(b.parent)] ? !cut_[size_t(a.parent)] : a.parent < b.parent;
        });
        firstPart_.assign(body_.primitives.size(), -1);
        lastPart_.assign(body_.primitives.size(), -1);
        for (int i = int(parts_.size()) - 1; i >= 0; --i) firstPart_[size_t(parts_[size_t(i)].parent)] = i;
        for (int i = 0; i < int(parts_.size()); ++i) lastPart_[size_t(parts_[size_t(i)].parent)] = i + 1;
        kept_ = int(std::count(cut_.begin(), cut_.end(), false));
    }

    // The faces of a part that lie on the visual faces of its parent: every vertex on the
    // parent face's plane (within the snap tolerance) and the same outward side. The clipper
    // keeps the parent's face planes, so the pieces' faces tile the parent's visual faces.
    // A sliver face narrower than the snap tolerance (a piece that meets the surface along a
    // line) is left out: it covers nothing, and its edges would match no neighbour's.
    std::vector<std::vector<int>> visualFacesOf(const Part& part) const {
        const auto& parent = body_.primitives[size_t(part.parent)];
        const auto& vertices = part.shape->vertices();
        std::vector<std::vector<int>> out;
        for (size_t f = 0; f < part.shape->faces().size(); ++f) {
            const auto& face = part.shape->faces()[f];
            double perimeter = 0.0;
            for (size_t k = 0; k < face.size(); ++k)
                perimeter += (vertices[size_t(face[(k + 1) % face.size()])] - vertices[size_t(face[k])]).norm();
            if (geometry::newellNormal(vertices, face).norm() <= tolerance_ * perimeter) continue;
            for (size_t g = 0; g < parent.faces().size(); ++g) {
                const auto& parentFace = parent.faces()[g];
                const bool visual = std::all_of(parentFace.begin(), parentFace.end(), [&](int v) {
                    return parent.globalIds()[size_t(v)] < visualCount_;
                });
                const geometry::Plane& plane = parent.planes()[g];
                if (!visual || plane.normal.dot(part.shape->planes()[f].normal) <= 0.0) continue;
                const bool on = std::all_of(face.begin(), face.end(), [&](int v) {
                    return std::abs(plane.signedDistance(part.shape->vertices()[size_t(v)])) <= tolerance_;
                });
                if (!on) continue;
                std::vector<int> ids;
                for (int v : face) ids.push_back(part.shape->globalIds()[size_t(v)]);
                out.push_back(std::move(ids));
                break;
            }
        }
        return out;
    }

    // Per body face, the primitives that carry it: those extruded from it (sourceFace), or for
    // a face of a closed convex part, the part whose face has the same ids.
    std::vector<std::vector<int>> carriers() const {
        std::vector<std::vector<int>> out(body_.visual.faces.size());
        std::map<std::vector<int>, int> closedFace; // sorted ids of a closed part's face → the part
        for (size_t p = 0; p < body_.primitives.size(); ++p) {
            const int source = body_.sourceFace[p];
            if (source >= 0) {
                out[size_t(source)].push_back(int(p));
                continue;
            }
            const auto& primitive = body_.primitives[p];
            for (const auto& face : primitive.faces()) {
                std::vector<int> ids;
                for (int v : face) ids.push_back(primitive.globalIds()[size_t(v)]);
                std::sort(ids.begin(), ids.end());
                closedFace.emplace(std::move(ids), int(p));
            }
        }
        for (size_t f = 0; f < out.size(); ++f) {
            if (!out[f].empty()) continue;
            std::vector<int> ids = body_.visual.faces[f];
            std::sort(ids.begin(), ids.end());
            if (const auto it = closedFace.find(ids); it != closedFace.end()) out[f].push_back(it->second);
        }
        return out;
    }

    // The body's faces in order; a face carried by a cut primitive is replaced, where it
    // stood, by the visual faces of all pieces of its carriers (once per carrier set).
    void buildSurface() {
        sourceFace_.assign(parts_.size(), -1);
        std::vector<char> emitted(body_.primitives.size(), 0);
        const auto carriedBy = carriers();
        for (size_t f = 0; f < body_.visual.faces.size(); ++f) {
            const auto& carrier = carriedBy[f];
            const bool cut = std::any_of(carrier.begin(), carrier.end(), [&](int p) { return cut_[size_t(p)]; });
            if (!cut) {
                for (int p : carrier)
                    if (body_.sourceFace[size_t(p)] >= 0) sourceFace_[size_t(firstPart_[size_t(p)])] = int(faces_.size());
                faces_.push_back(body_.visual.faces[f]);
                crack_.push_back(body_.visual.isCrackFace(f));
                continue;
            }
            // The replaced face's corners (and vertices an earlier subdivision inserted into
            // it) may lie inside the pieces' edges: repairTJunctions checks them too.
            for (int id : body_.visual.faces[f]) replacedCorners_.push_back(id);
            if (emitted[size_t(carrier.front())]) continue;
            for (int p : carrier) {
                emitted[size_t(p)] = 1;
                for (int i = firstPart_[size_t(p)]; i < lastPart_[size_t(p)]; ++i) {
                    auto own = visualFacesOf(parts_[size_t(i)]);
                    // An extruded piece keeps its one visual face as its source face.
                    if (body_.sourceFace[size_t(p)] >= 0 && own.size() == 1) sourceFace_[size_t(i)] = int(faces_.size());
                    for (auto& face : own) {
                        faces_.push_back(std::move(face));
                        crack_.push_back(body_.visual.isCrackFace(f)); // a crack face stays one where re-tiled
                    }
                }
            }
        }
    }

    // The body's visual ids stay; new visual vertices follow in the order the faces first use
    // them; then every other id in the order the primitives use them.
    void renumberIds() {
        int largest = body_.globalIdCount - 1;
        for (const Part& p : parts_)
            for (int id : p.shape->globalIds()) largest = std::max(largest, id);
        newId_.assign(size_t(largest) + 1, -1);
        std::vector<const Eigen::Vector3d*> at(newId_.size(), nullptr);
        for (const Part& p : parts_)
            for (size_t v = 0; v < p.shape->vertices().size(); ++v) {
                const auto*& slot = at[size_t(p.shape->globalIds()[v])];
                if (!slot) slot = &p.shape->vertices()[v];
            }
        positions_ = body_.visual.positions;
        for (int i = 0; i < visualCount_; ++i) newId_[size_t(i)] = i;
        idCount_ = visualCount_;
        for (auto& face : faces_)
            for (int& id : face) {
                int& mapped = newId_[size_t(id)];
                if (mapped < 0) {
                    mapped = idCount_++;
                    positions_.push_back(*at[size_t(id)]);
                }
                id = mapped;
            }
        for (const Part& p : parts_)
            for (int id : p.shape->globalIds())
                if (newId_[size_t(id)] < 0) newId_[size_t(id)] = idCount_++;
    }

    // A visual vertex of the cut region (new, or a corner of a replaced face) that lies inside
    // an edge of a face (a body face next to a cut one, or a piece face cut differently from
    // its neighbour) is inserted into that face, so the surface has no T-junction and cannot
    // open there when the primitives move.
    void repairTJunctions() {
        std::vector<int> fresh(size_t(int(positions_.size()) - visualCount_));
        std::iota(fresh.begin(), fresh.end(), visualCount_);
        fresh.insert(fresh.end(), replacedCorners_.begin(), replacedCorners_.end());
        std::sort(fresh.begin(), fresh.end());
        fresh.erase(std::unique(fresh.begin(), fresh.end()), fresh.end());
        if (fresh.empty()) return;
        std::sort(fresh.begin(), fresh.end(), [&](int a, int b) { return positions_[size_t(a)].x() < positions_[size_t(b)].x(); });
        geometry::Aabb region; // of the candidates: most faces of a large body are far from it
        for (int c : fresh) region.extend(positions_[size_t(c)]);
        region = region.inflated(tolerance_);
        std::vector<std::pair<double, int>> inside;
        for (auto& face : faces_) {
            geometry::Aabb box;
            for (int v : face) box.extend(positions_[size_t(v)]);
            if (!box.overlaps(region)) continue;
            std::vector<int> out;
            for (size_t k = 0; k < face.size(); ++k) {
                const int a = face[k], b = face[(k + 1) % face.size()];
                out.push_back(a);
                const Eigen::Vector3d& pa = positions_[size_t(a)];
                const Eigen::Vector3d edge = positions_[size_t(b)] - pa;
                const double length2 = edge.squaredNorm();
                if (length2 <= 0.0) continue;
                const double lo = std::min(pa.x(), pa.x() + edge.x()) - tolerance_;
                const double hi = std::max(pa.x(), pa.x() + edge.x()) + tolerance_;
                auto it = std::lower_bound(fresh.begin(), fresh.end(), lo,
                                           [&](int c, double x) { return positions_[size_t(c)].x() < x; });
                inside.clear();
                for (; it != fresh.end() && positions_[size_t(*it)].x() <= hi; ++it) {
                    if (*it == a || *it == b) continue;
                    const Eigen::Vector3d d = positions_[size_t(*it)] - pa;
                    const double t = d.dot(edge) / length2;
                    if (t <= 0.0 || t >= 1.0 || (d - t * edge).norm() > tolerance_) continue;
                    if (std::find(face.begin(), face.end(), *it) != face.end()) continue;
                    inside.emplace_back(t, *it);
                }
                std::sort(inside.begin(), inside.end());
                for (const auto& [t, c] : inside) out.push_back(c);
            }
            face = std::move(out);
        }
    }

    // Kept where neither primitive was cut; recomputed among the pieces of a cut primitive and
    // of its connected neighbours.
    std::vector<std::pair<int, int>> connections() const {
        std::vector<std::pair<int, int>> out;
        auto touching = [&](int a, int b) {
            const auto& sa = *parts_[size_t(a)].shape;
            const auto& sb = *parts_[size_t(b)].shape;
            return sa.bounds().inflated(body_.contactTolerance).overlaps(sb.bounds()) &&
                   geometry::withinTolerance(sa, sb, body_.contactTolerance);
        };
        for (const auto& [p, q] : body_.connections) {
            if (!cut_[size_t(p)] && !cut_[size_t(q)]) {
                out.emplace_back(firstPart_[size_t(p)], firstPart_[size_t(q)]);
                continue;
            }
            for (int a = firstPart_[size_t(p)]; a < lastPart_[size_t(p)]; ++a)
                for (int b = firstPart_[size_t(q)]; b < lastPart_[size_t(q)]; ++b)
                    if (touching(a, b)) out.emplace_back(std::min(a, b), std::max(a, b));
        }
        for (size_t p = 0; p < body_.primitives.size(); ++p)
            for (int a = firstPart_[p]; a < lastPart_[p]; ++a)
                for (int b = a + 1; b < lastPart_[p]; ++b)
                    if (touching(a, b)) out.emplace_back(a, b);
        std::sort(out.begin(), out.end());
        out.erase(std::unique(out.begin(), out.end()), out.end());
        return out;
    }

    const geometry::PhysicalMesh& body_;
    double tolerance_;
    int visualCount_;
    std::vector<geometry::ConvexPolyhedron> pieces_; // the cut pieces, in fracture-wide ids
    std::vector<Part> parts_;
    std::vector<int> firstPart_, lastPart_; // per body primitive: its parts [first, last)
    int kept_ = 0;                          // uncut primitives (the first parts)
    std::vector<bool> cut_;      // per body primitive: some piece of it was clipped
    std::vector<std::vector<int>> faces_;
    std::vector<bool> crack_; // per face: the body face it tiles was a crack face
    std::vector<int> sourceFace_; // per part
    std::vector<int> replacedCorners_; // body visual ids of the faces replaced by pieces' faces
    std::vector<int> newId_;      // fracture-wide id → subdivided body's id, or -1
    std::vector<Eigen::Vector3d> positions_;
    int idCount_ = 0;
};

// The body as it is (nothing was cut).
SubdivisionResult unchanged(const geometry::PhysicalMesh& body) {
    SubdivisionResult result;
    result.mesh = body;
    result.parents.resize(body.primitives.size());
    std::iota(result.parents.begin(), result.parents.end(), 0);
    result.clipped.assign(body.primitives.size(), false);
    result.kept = int(body.primitives.size());
    return result;
}

} // namespace

SubdivisionResult subdivideMesh(const geometry::PhysicalMesh& body, const FracturePattern& pattern,
                                const Placement& where, const CutSettings& settings) {
    // The cut alone: the pieces become primitives of this one body, so the fragments' islands
    // and surfaces that fractureMesh would build are not needed.
    CutPieces cut = cutMesh(body, pattern, where, settings);
    const double cutSeconds = cut.seconds;
    const auto t = SteadyClock::now();
    SubdivisionResult result = cut.primitivesCut == 0 ? unchanged(body) : Assembler(body, settings).run(std::move(cut));
    result.cutSeconds = cutSeconds;
    result.assemblySeconds = secondsSince(t);
    return result;
}

} // namespace shatter::fracture
