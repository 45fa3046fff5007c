#include <shatter/plugin/lattice/Lattice.h>

#include <algorithm>
#include <cmath>

namespace shatter::lattice {

Lattice::Lattice(TetMesh mesh, const MaterialSettings& material) : mesh_(std::move(mesh)), material_(material) {
    validateTetMesh(mesh_);
    material_.check(mesh_.name);
    faces_ = buildTetFaces(mesh_);
    particles_.reserve(mesh_.tets.size());
    for (const Tet& t : mesh_.tets) {
        Particle p;
        p.position = centroid(mesh_, t);
        p.volume = signedVolume(mesh_, t);
        p.mass = p.volume * material_.density;
        totalMass_ += p.mass;
        particles_.push_back(p);
    }
    links_.reserve(faces_.shared.size());
    for (const SharedFace& f : faces_.shared) {
        Link l;
        l.a = f.tetA;
        l.b = f.tetB;
        const Eigen::Vector3d d = particles_[l.a].position - particles_[l.b].position;
        l.length = d.norm();
        l.normal = d / l.length;
        const Eigen::Vector3d& p0 = mesh_.nodes[f.nodes[0]];
        const Eigen::Vector3d& p1 = mesh_.nodes[f.nodes[1]];
        const Eigen::Vector3d& p2 = mesh_.nodes[f.nodes[2]];
        l.area = 0.5 * (p1 - p0).cross(p2 - p0).norm();
        l.faceCentre = (p0 + p1 + p2) / 3.0;
        l.face = f.nodes;
        l.baseStrength = l.strength = l.area * material_.strength;
        links_.push_back(l);
    }
    broken_.assign(links_.size(), 0);
    // Per-particle link lists in link order (compressed rows).
    linkStart_.assign(particles_.size() + 1, 0);
    for (const Link& l : links_) {
        ++linkStart_[l.a + 1];
        ++linkStart_[l.b + 1];
    }
    for (size_t i = 0; i < particles_.size(); ++i) linkStart_[i + 1] += linkStart_[i];
    linkIndex_.resize(links_.size() * 2);
    std::vector<int> fill(linkStart_.begin(), linkStart_.end() - 1);
    for (int k = 0; k < int(links_.size()); ++k) {
        linkIndex_[fill[links_[k].a]++] = k;
        linkIndex_[fill[links_[k].b]++] = k;
    }
}

void Lattice::scaleStrength(int link, double factor) {
    links_[link].baseStrength *= factor;
    links_[link].strength *= factor;
}

void Lattice::weaken(int link, double amount) { links_[link].strength -= std::max(0.0, amount); }

void Lattice::breakLink(int link) {
    if (links_[link].broken) return;
    links_[link].broken = true;
    broken_[size_t(link)] = 1;
    ++brokenCount_;
}

void Lattice::joinLink(int link) {
    if (links_[link].broken) --brokenCount_, joined_.push_back(link);
    links_[link].broken = false;
    broken_[size_t(link)] = 0;
    links_[link].baseStrength = links_[link].strength = INFINITY;
}

std::vector<int> tetsWithFaceOnPlane(const TetMesh& mesh, const Eigen::Vector3d& normal, double offset, double tolerance) {
    const Eigen::Vector3d n = normal.normalized();
    std::vector<int> out;
    for (int t = 0; t < int(mesh.tets.size()); ++t)
        for (const auto& face : outwardFaces(mesh.tets[t])) {
            const bool on = std::all_of(face.begin(), face.end(), [&](int v) {
                return std::abs(n.dot(mesh.nodes[v]) - offset) <= tolerance;
            });
            if (on) {
                out.push_back(t);
                break;
            }
        }
    return out;
}

} // namespace shatter::lattice
