#include <shatter/plugin/geometry/PhysicalMeshBuilder.h>

#include <shatter/plugin/geometry/AabbTree.h>
#include <shatter/plugin/geometry/ClosedConvexParts.h>
#include <shatter/plugin/geometry/ClosedSurface.h>
#include <shatter/plugin/geometry/Connectivity.h>
#include <shatter/plugin/geometry/Extrusion.h>
#include <shatter/plugin/common/InputError.h>
#include <shatter/plugin/geometry/Polygon.h>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace shatter::geometry {

namespace {

// Tolerances relative to the body's bounding-box diagonal (see PhysicalMesh.h).
constexpr double kDefaultThickness = 1e-2;
constexpr double kDefaultContactTolerance = 1e-4;
constexpr double kZeroArea = 1e-12;    // of diagonal²: Newell normal this short is no face
constexpr double kConvexity = 1e-7;    // closed parts: vertex allowed in front of a face plane
constexpr double kPlanarity = 1e-6;    // faces: distance from the Newell plane of a flat face
constexpr double kZeroVolume = 1e-12;  // of diagonal³: a closed surface enclosing less encloses nothing
// Sizes in metres whose volume integrals stay far from overflow and underflow (the area
// vectors' squared norms overflow at coordinates near 1e77 m, volumes underflow near 1e-100 m).
constexpr double kFarthest = 1e12;
constexpr double kSmallest = 1e-9;
// What one primitive costs once the body is in a world (its polyhedron, mass, connections,
// group-shape leaf and visual share), rounded up: peak RSS of shatter-drop --frames 1 over
// that with a one-box mesh (118 MB), per primitive: 4.7 kB with Spot (5,856 primitives),
// 4.3 kB with a sheet of 45,000 triangles.
constexpr double kBytesPerPrimitive = 5000;
// maxOverlapsPerPrimitive counts at least this many primitives: a small fan (a cylinder's
// cap) has all n²/2 pairs touching, legitimately.
constexpr long long kFewestPrimitivesForPairs = 1000;

class Builder {
public:
    Builder(const std::string& name, const std::vector<Eigen::Vector3d>& positions,
            const std::vector<std::vector<int>>& faces, const std::vector<std::string>& labels,
            const PhysicalMeshSettings& settings, long long primitivesBefore)
        : name_(name), positions_(positions), faces_(faces), labels_(labels), settings_(settings),
          primitivesBefore_(primitivesBefore) {}

    PhysicalMesh run() {
        checkSettings();
        checkFaces();
        keepUsableFaces();
        chooseLengths();
        makePrimitives();
        measureEnclosedVolume();
        checkPairCount();
        mesh_.connections = touchingPairs(mesh_.primitives, mesh_.contactTolerance);
        carrySolidMass();
        for (const auto& p : mesh_.primitives) mesh_.mass += p.massProperties(mesh_.density);
        return std::move(mesh_);
    }

private:
    std::string prefix() const { return "body '" + name_ + "': "; }
    std::string label(int inputFace) const {
        return labels_.empty() ? "face " + std::to_string(inputFace) : labels_[inputFace];
    }

    void checkSettings() const { // the settings themselves were checked by the caller
        if (!labels_.empty() && labels_.size() != faces_.size())
            throw InputError(prefix() + "has " + std::to_string(labels_.size()) + " face labels for " +
                             std::to_string(faces_.size()) + " faces");
    }

    void checkFaces() {
        const int n = int(positions_.size());
        for (size_t f = 0; f < faces_.size(); ++f)
            for (int v : faces_[f]) {
                if (v < 0 || v >= n)
                    throw InputError(prefix() + label(int(f)) + ": vertex index " + std::to_string(v) +
                                     " is out of range (" + std::to_string(n) + " vertices)");
                if (!positions_[v].allFinite())
                    throw InputError(prefix() + label(int(f)) + ": vertex " + std::to_string(v) +
                                     " has a non-finite coordinate");
                if (!(positions_[v].cwiseAbs().maxCoeff() <= kFarthest)) {
                    std::ostringstream msg;
                    msg << prefix() << label(int(f)) << ": vertex " << v << " has a coordinate of "
                        << positions_[v].cwiseAbs().maxCoeff() << " m, beyond the " << kFarthest
                        << " m the geometry handles (check units and scale)";
                    throw InputError(msg.str());
                }
                bounds_.extend(positions_[v]);
            }
        diagonal_ = bounds_.diagonal();
        if (!faces_.empty() && !(diagonal_ >= kSmallest)) {
            std::ostringstream msg;
            msg << prefix() << "is " << diagonal_ << " m across, below the " << kSmallest
                << " m the geometry handles (check units and scale)";
            throw InputError(msg.str());
        }
    }

    void keepUsableFaces() {
        std::vector<std::string> skipped;
        for (size_t f = 0; f < faces_.size(); ++f) {
            std::vector<int> polygon = faces_[f];
            if (cleanPolygon(positions_, polygon, kZeroArea * diagonal_ * diagonal_, true) != PolygonDefect::Kept) {
                skipped.push_back(label(int(f)));
                continue;
            }
            mesh_.visual.faces.push_back(std::move(polygon));
            inputFace_.push_back(int(f));
        }
        if (mesh_.visual.faces.empty()) {
            std::string msg = prefix() + "no faces";
            if (!faces_.empty()) msg += " (all " + std::to_string(faces_.size()) + " faces are degenerate)";
            throw InputError(msg);
        }
        if (!skipped.empty())
            mesh_.warnings.push_back(prefix() + "skipped " + std::to_string(skipped.size()) + " degenerate face" +
                                     (skipped.size() == 1 ? "" : "s") + " (" + listed(skipped) + ")");
    }

    static std::string listed(const std::vector<std::string>& items) {
        std::string out;
        for (size_t i = 0; i < items.size() && i < 5; ++i) out += (i ? ", " : "") + items[i];
        if (items.size() > 5) out += ", ...";
        return out;
    }

    void chooseLengths() {
        mesh_.name = name_;
        mesh_.visual.positions = positions_;
        mesh_.thickness = settings_.thickness > 0.0 ? settings_.thickness : kDefaultThickness * diagonal_;
        mesh_.density = settings_.density;
        mesh_.contactTolerance =
            settings_.contactTolerance > 0.0 ? settings_.contactTolerance : kDefaultContactTolerance * diagonal_;
    }

    // Primitives in face order: a closed convex part appears where its first face is.
    void makePrimitives() {
        auto& faces = mesh_.visual.faces;
        std::vector<int> partOf(faces.size(), -1);
        std::vector<ClosedConvexPart> parts = findClosedConvexParts(positions_, faces, kConvexity * diagonal_);
        long long count = (long long)parts.size();
        for (size_t p = 0; p < parts.size(); ++p) {
            for (int f : parts[p].faces) partOf[f] = int(p);
            if (parts[p].flipped) flip(parts[p]);
        }
        for (size_t f = 0; f < faces.size(); ++f)
            if (partOf[f] < 0) count += prismCount(positions_, faces[f], kPlanarity * diagonal_);
        checkPrimitiveCount(count);
        const int visualCount = int(positions_.size());
        for (size_t f = 0; f < faces.size(); ++f) {
            const int p = partOf[f];
            if (p >= 0) {
                if (parts[p].faces.front() != int(f)) continue;
                mesh_.primitives.push_back(std::move(parts[p].primitive));
                mesh_.sourceFace.push_back(-1);
                continue;
            }
            for (auto& prism : extrudeFace(positions_, faces[f], mesh_.thickness, kPlanarity * diagonal_, visualCount,
                                           prefix() + label(inputFace_[f]))) {
                mesh_.primitives.push_back(std::move(prism));
                mesh_.sourceFace.push_back(int(f));
            }
            extruded_ = true;
        }
        mesh_.globalIdCount = extruded_ ? 2 * visualCount : visualCount;
    }

    void checkPrimitiveCount(long long count) const {
        const long long total = primitivesBefore_ + count;
        if (total <= settings_.maxPrimitives) return;
        std::ostringstream msg;
        msg << prefix() << "its faces make " << count << " primitives";
        if (primitivesBefore_ > 0) msg << " (" << total << " with the file's earlier bodies)";
        msg << ", about " << std::ceil(double(total) * kBytesPerPrimitive / 1e6) << " MB, more than the limit of "
            << settings_.maxPrimitives << " (raise it with PhysicalMeshSettings::maxPrimitives, --max-primitives)";
        throw InputError(msg.str());
    }

    // The pairs touchingPairs will test (boxes grown by half the tolerance overlap), counted
    // up to the limit only: a mesh folded onto itself has nearly all n² of them. The limit is
    // per primitive, so the time stays linear in the primitive count (itself limited).
    void checkPairCount() const {
        const long long n = (long long)mesh_.primitives.size();
        const long long limit = settings_.maxOverlapsPerPrimitive * std::max(n, kFewestPrimitivesForPairs);
        std::vector<Aabb> boxes;
        boxes.reserve(mesh_.primitives.size());
        for (const auto& p : mesh_.primitives) boxes.push_back(p.bounds().inflated(0.5 * mesh_.contactTolerance));
        struct OverLimit {};
        long long pairs = 0;
        try {
            AabbTree(boxes).selfPairs([&](int, int) {
                if (++pairs > limit) throw OverLimit{};
            });
        } catch (const OverLimit&) {
            std::ostringstream msg;
            msg << prefix() << "the boxes of its " << n << " primitives overlap in more than " << limit
                << " pairs, each to be tested for contact (a mesh folded onto itself?): more than "
                << settings_.maxOverlapsPerPrimitive << " per primitive (raise it with "
                << "PhysicalMeshSettings::maxOverlapsPerPrimitive, --max-overlaps-per-primitive)";
            throw InputError(msg.str());
        }
    }

    // Fill::Solid: the volume the kept faces enclose when they all form closed surfaces
    // (after makePrimitives, which turns closed convex parts wound inward outward).
    void measureEnclosedVolume() {
        if (settings_.fill != Fill::Solid) return;
        const std::vector<int> rep = coincidentRepresentatives(positions_);
        std::vector<std::vector<int>> welded = mesh_.visual.faces;
        for (auto& face : welded)
            for (int& v : face) v = rep[v];
        if (!isClosedSurface(welded)) return;
        double volume = polyhedronMassProperties(positions_, mesh_.visual.faces, 1.0).volume;
        if (volume < 0.0) {
            std::ostringstream msg;
            msg << prefix() << "its closed surface is wound inward (negative volume); its solid volume is taken as "
                << -volume << " m^3";
            mesh_.warnings.push_back(msg.str());
            volume = -volume;
        }
        if (!(volume > kZeroVolume * diagonal_ * diagonal_ * diagonal_)) {
            std::ostringstream msg;
            msg << prefix() << "its closed surface encloses no volume (" << volume
                << " m^3: a flattened solid?); make it a shell with fill Shell (--fill shell)";
            throw InputError(msg.str());
        }
        mesh_.enclosedVolume = volume;
    }

    // Fill::Solid over a shell of extruded faces: the primitives carry the enclosed solid's mass.
    void carrySolidMass() {
        if (mesh_.enclosedVolume == 0.0 || !extruded_) return;
        double primitiveVolume = 0.0;
        for (const auto& p : mesh_.primitives) primitiveVolume += p.volume();
        mesh_.density = settings_.density * (mesh_.enclosedVolume / primitiveVolume);
    }

    void flip(const ClosedConvexPart& part) {
        std::vector<std::string> which;
        for (int f : part.faces) {
            std::reverse(mesh_.visual.faces[f].begin(), mesh_.visual.faces[f].end());
            which.push_back(label(inputFace_[f]));
        }
        mesh_.warnings.push_back(prefix() + "the closed part (" + listed(which) +
                                 ") was wound inward (negative volume); flipped its faces");
    }

    const std::string& name_;
    const std::vector<Eigen::Vector3d>& positions_;
    const std::vector<std::vector<int>>& faces_;
    const std::vector<std::string>& labels_;
    const PhysicalMeshSettings& settings_;
    const long long primitivesBefore_;
    bool extruded_ = false;
    Aabb bounds_;
    double diagonal_ = 0.0;
    std::vector<int> inputFace_; // per kept face: its index in the input
    PhysicalMesh mesh_;
};

} // namespace

PhysicalMesh buildLabelledPhysicalMesh(const std::string& name, const std::vector<Eigen::Vector3d>& positions,
                                       const std::vector<std::vector<int>>& faces,
                                       const std::vector<std::string>& faceLabels,
                                       const PhysicalMeshSettings& settings, long long primitivesBefore) {
    settings.check(name);
    const double factor = settings.metresPerInputUnit();
    if (factor == 1.0) return Builder(name, positions, faces, faceLabels, settings, primitivesBefore).run();
    std::vector<Eigen::Vector3d> metres;
    metres.reserve(positions.size());
    for (const Eigen::Vector3d& p : positions) metres.push_back(factor * p);
    return Builder(name, metres, faces, faceLabels, settings, primitivesBefore).run();
}

PhysicalMesh buildPhysicalMesh(const std::string& name, const std::vector<Eigen::Vector3d>& positions,
                               const std::vector<std::vector<int>>& faces, const PhysicalMeshSettings& settings) {
    return buildLabelledPhysicalMesh(name, positions, faces, {}, settings, 0);
}

int PhysicalMesh::componentCount() const { return countComponents(int(primitives.size()), connections); }

} // namespace shatter::geometry
