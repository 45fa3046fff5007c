#include "demos/runner/RunRecording.h"

#include <map>
#include <stdexcept>

namespace shatter::demo {

namespace {

geometry::VisualMesh inBodyCoordinates(const NamedMesh& m) {
    geometry::VisualMesh local = m.mesh;
    const Eigen::Isometry3d toBody = m.pose.inverse();
    for (auto& p : local.positions) p = toBody * p;
    return local;
}

double extent(const geometry::VisualMesh& mesh) {
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(INFINITY), hi = Eigen::Vector3d::Constant(-INFINITY);
    for (const auto& p : mesh.positions) {
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
    }
    return mesh.positions.empty() ? 0.0 : (hi - lo).norm();
}

// Whether `world`, taken to body coordinates by `toBody`, is `shape` (without building the
// body-coordinate copy: most bodies keep their shape most frames).
bool sameShape(const geometry::VisualMesh& shape, const geometry::VisualMesh& world, const Eigen::Isometry3d& toBody) {
    if (shape.positions.size() != world.positions.size() || shape.faces != world.faces ||
        shape.crackFace != world.crackFace)
        return false;
    const double tolerance = 1e-4 * extent(shape);
    for (size_t i = 0; i < shape.positions.size(); ++i)
        if (!((toBody * world.positions[i] - shape.positions[i]).cwiseAbs().maxCoeff() <= tolerance)) return false;
    return true;
}

} // namespace

const BodyKey* BodyTrack::at(int frame) const {
    if (frame < firstFrame || frame > lastFrame()) return nullptr;
    const BodyKey& key = keys[size_t(frame - firstFrame)];
    return key.shape >= 0 ? &key : nullptr;
}

void RunRecording::add(int frame, const std::vector<NamedMesh>& meshes, int events) {
    if (frame != frames_ + 1) throw std::logic_error("RunRecording: frames must come one after the other");
    frames_ = frame;
    events_.push_back(events);
    std::map<std::string, int> seen; // occurrences of each name in this frame
    std::map<std::string, size_t> byName;
    for (size_t t = 0; t < tracks_.size(); ++t) byName[tracks_[t].name] = t;
    for (const NamedMesh& m : meshes) {
        const int n = ++seen[m.name];
        const std::string name = n == 1 ? m.name : m.name + "#" + std::to_string(n);
        auto found = byName.find(name);
        if (found == byName.end()) {
            BodyTrack track;
            track.name = name;
            track.ground = m.ground;
            track.outlined = m.outlined;
            track.firstFrame = frame;
            found = byName.emplace(name, tracks_.size()).first;
            tracks_.push_back(std::move(track));
        }
        BodyTrack& track = tracks_[found->second];
        // Frames the body missed since it was last seen.
        while (track.lastFrame() < frame - 1) track.keys.push_back(BodyKey{Eigen::Vector3d::Zero(), Eigen::Quaterniond::Identity(), -1});
        BodyKey key{m.pose.translation(), Eigen::Quaterniond(m.pose.rotation()).normalized(), -1};
        const BodyKey* previous = track.keys.empty() ? nullptr : &track.keys.back();
        if (previous && previous->shape >= 0 && sameShape(track.shapes[size_t(previous->shape)], m.mesh, m.pose.inverse()))
            key.shape = previous->shape;
        else {
            key.shape = int(track.shapes.size());
            track.shapes.push_back(inBodyCoordinates(m));
        }
        if (previous && previous->rotation.dot(key.rotation) < 0) key.rotation.coeffs() *= -1;
        track.keys.push_back(key);
    }
}

std::vector<NamedMesh> RunRecording::meshesAt(int frame) const {
    std::vector<NamedMesh> out;
    for (const BodyTrack& track : tracks_) {
        const BodyKey* key = track.at(frame);
        if (!key) continue;
        NamedMesh m{track.name, track.shapes[size_t(key->shape)], track.outlined, track.ground, Eigen::Isometry3d::Identity()};
        m.pose.translate(key->translation);
        m.pose.rotate(key->rotation);
        for (auto& p : m.mesh.positions) p = m.pose * p;
        out.push_back(std::move(m));
    }
    return out;
}

} // namespace shatter::demo
