#include <shatter/plugin/geometry/PhysicalMeshBuilder.h>

#include <shatter/plugin/geometry/ClosedConvexParts.h>
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

class Builder {
public:
    Builder(const std::string& name, const std::vector<Eigen::Vector3d>& positions,
            const std::vector<std::vector<int>>& faces, const std::vector<std::string>& labels,
            const PhysicalMeshSettings& settings)
        : name_(name), positions_(positions), faces_(faces), labels_(labels), settings_(settings) {}

    PhysicalMesh run() {
        checkSettings();
        checkFaces();
        keepUsableFaces();
        chooseLengths();
        makePrimitives();
        mesh_.connections = touchingPairs(mesh_.primitives, mesh_.contactTolerance);
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
                bounds_.extend(positions_[v]);
            }
        diagonal_ = bounds_.diagonal();
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
        for (size_t p = 0; p < parts.size(); ++p) {
            for (int f : parts[p].faces) partOf[f] = int(p);
            if (parts[p].flipped) flip(parts[p]);
        }
        const int visualCount = int(positions_.size());
        bool extruded = false;
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
            extruded = true;
        }
        mesh_.globalIdCount = extruded ? 2 * visualCount : visualCount;
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
    Aabb bounds_;
    double diagonal_ = 0.0;
    std::vector<int> inputFace_; // per kept face: its index in the input
    PhysicalMesh mesh_;
};

} // namespace

PhysicalMesh buildLabelledPhysicalMesh(const std::string& name, const std::vector<Eigen::Vector3d>& positions,
                                       const std::vector<std::vector<int>>& faces,
                                       const std::vector<std::string>& faceLabels,
                                       const PhysicalMeshSettings& settings) {
    settings.check(name);
    const double factor = settings.metresPerInputUnit();
    if (factor == 1.0) return Builder(name, positions, faces, faceLabels, settings).run();
    std::vector<Eigen::Vector3d> metres;
    metres.reserve(positions.size());
    for (const Eigen::Vector3d& p : positions) metres.push_back(factor * p);
    return Builder(name, metres, faces, faceLabels, settings).run();
}

PhysicalMesh buildPhysicalMesh(const std::string& name, const std::vector<Eigen::Vector3d>& positions,
                               const std::vector<std::vector<int>>& faces, const PhysicalMeshSettings& settings) {
    return buildLabelledPhysicalMesh(name, positions, faces, {}, settings);
}

int PhysicalMesh::componentCount() const { return countComponents(int(primitives.size()), connections); }

} // namespace shatter::geometry
