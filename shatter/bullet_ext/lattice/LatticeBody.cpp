#include <shatter/bullet_ext/lattice/LatticeBody.h>

#include <shatter/bullet_ext/Convert.h>
#include <shatter/bullet_ext/VisualBody.h>
#include <shatter/plugin/common/InputError.h>
#include <shatter/plugin/lattice/Fragments.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace shatter {

namespace {

lattice::Lattice buildLattice(lattice::TetMesh mesh, const LatticeSettings& s) {
    mesh.name = meshNameFor(mesh, s);
    s.check(int(mesh.tets.size()));
    if (!s.anchorRegions.empty() || !s.anchorTo.empty())
        throw InputError("body '" + s.name + "': anchor regions and bodies are resolved where the body is placed (resolveAnchors)");
    lattice::Lattice l(std::move(mesh), s.material);
    for (int t : s.fixedTets) l.setFixed(t, true);
    lattice::applyCleavingPlanes(l, s.cleavingPlanes);
    lattice::applyNoise(l, s.noise, s.seed);
    return l;
}

} // namespace

std::string meshNameFor(const lattice::TetMesh& mesh, const LatticeSettings& settings) {
    return mesh.name.empty() || mesh.name == "tet mesh" ? settings.name : mesh.name;
}

LatticeBody::LatticeBody(int id, lattice::TetMesh mesh, const LatticeSettings& settings)
    : id_(id), settings_(settings), lattice_(buildLattice(std::move(mesh), settings)), random_(settings.seed),
      slivers_(lattice::bindSlivers(lattice_, settings.sliverQuality)) {
    tetMass_.reserve(lattice_.mesh().tets.size());
    for (const lattice::Tet& tet : lattice_.mesh().tets)
        tetMass_.push_back(lattice::tetMassProperties(lattice_.mesh(), tet, lattice_.material().density));
}

geometry::MassProperties LatticeBody::massOf(const std::vector<int>& particles) const {
    return lattice::pieceMassProperties(tetMass_, particles);
}

double kineticEnergy(const btRigidBody& rigid) {
    if (rigid.getInvMass() == 0) return 0.0;
    const btVector3 w = rigid.getAngularVelocity() * rigid.getWorldTransform().getBasis(); // Rᵀ ω: body axes
    const btVector3 inv = rigid.getInvInertiaDiagLocal();
    double spin = 0.0;
    for (int i = 0; i < 3; ++i)
        if (inv[i] > 0) spin += double(w[i]) * double(w[i]) / double(inv[i]);
    return 0.5 * (double(rigid.getLinearVelocity().length2()) / double(rigid.getInvMass()) + spin);
}

double LatticeBody::mechanicalEnergy(const btVector3& gravity) const {
    double energy = 0.0;
    for (const Piece& p : pieces_) {
        const btRigidBody& rigid = p.body->rigidBody();
        // Static (anchored, frozen) bodies keep their frame, not one at the centre of mass.
        const Eigen::Vector3d com = toEigen(rigid.getWorldTransform()) * p.body->meshToBody() * p.mass.centerOfMass;
        energy += kineticEnergy(rigid) - p.mass.mass * toEigen(gravity).dot(com);
    }
    return energy;
}

LatticeBody::Speeds LatticeBody::fastestPieces() const {
    Speeds out;
    for (const Piece& p : pieces_) {
        const btRigidBody& rigid = p.body->rigidBody();
        btVector3 centre;
        btScalar radius;
        rigid.getCollisionShape()->getBoundingSphere(centre, radius);
        const double v = rigid.getLinearVelocity().length();
        if (v > out.centre) out.centre = v, out.tets = int(p.lattice.particles.size());
        out.point = std::max(out.point, v + double(rigid.getAngularVelocity().length() * radius));
    }
    return out;
}

double LatticeBody::currentMass() const {
    double m = 0.0;
    for (const Piece& p : pieces_) m += p.mass.mass;
    return m;
}

int LatticeBody::frozenPieceCount() const {
    return int(std::count_if(pieces_.begin(), pieces_.end(), [](const Piece& p) { return p.frozen; }));
}

std::string LatticeBody::nextPieceName() {
    // The unbroken body keeps the body's name; fragments are name.f1, name.f2, ...
    std::string n = piecesMade_ == 0 ? name() : name() + ".f" + std::to_string(piecesMade_);
    ++piecesMade_;
    return n;
}

template <typename Primitive>
geometry::PhysicalMesh LatticeBody::meshOf(const std::vector<int>& particles, const std::string& name,
                                           const Primitive& primitive) const {
    const lattice::TetMesh& mesh = lattice_.mesh();
    geometry::PhysicalMesh out;
    out.name = name;
    // Nodes renumbered compactly per piece, so each piece's visual mesh holds only its own: in
    // the body's node scratch (all -1 between calls), reset below node by node, so that a
    // fragment of a few tets costs no pass over the body's nodes (nor a hash map's nodes).
    std::vector<int>& local = localNode_;
    local.resize(mesh.nodes.size(), -1);
    std::vector<int> nodes; // those given a number, in that order
    // Reset on every way out: a `primitive` that throws must not leave numbers behind.
    struct ResetScratch {
        std::vector<int>& local;
        const std::vector<int>& nodes;
        ~ResetScratch() {
            for (int n : nodes) local[size_t(n)] = -1;
        }
    } reset{local, nodes};
    auto localId = [&](int node) {
        int& id = local[size_t(node)];
        if (id < 0) {
            id = int(out.visual.positions.size());
            out.visual.positions.push_back(mesh.nodes[node]);
            nodes.push_back(node);
        }
        return id;
    };
    out.primitives.reserve(particles.size());
    for (int t : particles) {
        const lattice::Tet& tet = mesh.tets[t];
        std::vector<int> ids(4);
        for (int k = 0; k < 4; ++k) ids[size_t(k)] = localId(tet[k]);
        out.primitives.push_back(primitive(t, std::move(ids)));
    }
    out.sourceFace.assign(particles.size(), -1);
    for (const auto& face : lattice::surfaceFaces(lattice_, particles))
        out.visual.faces.push_back({localId(face[0]), localId(face[1]), localId(face[2])});
    out.globalIdCount = int(out.visual.positions.size());
    out.mass = massOf(particles);
    out.density = lattice_.material().density;
    return out;
}

geometry::PhysicalMesh LatticeBody::physicalMesh(const std::vector<int>& particles, const std::string& name) const {
    const lattice::TetMesh& mesh = lattice_.mesh();
    static const std::vector<std::vector<int>> kFaces = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
    return meshOf(particles, name, [&](int t, std::vector<int> ids) {
        std::vector<Eigen::Vector3d> corners;
        for (int n : mesh.tets[t]) corners.push_back(mesh.nodes[n]);
        return geometry::ConvexPolyhedron::create(std::move(corners), kFaces, std::move(ids),
                                                  name + " tet " + std::to_string(t));
    });
}

geometry::PhysicalMesh LatticeBody::partMesh(const geometry::PhysicalMesh& from, const std::vector<int>& fromParticles,
                                             const std::vector<int>& particles, const std::string& name) const {
    // Both lists sorted: tet t's primitive in `from` is found walking forward.
    auto at = fromParticles.begin();
    return meshOf(particles, name, [&](int t, std::vector<int> ids) {
        at = std::lower_bound(at, fromParticles.end(), t);
        if (at == fromParticles.end() || *at != t)
            throw std::logic_error("LatticeBody::partMesh: tet " + std::to_string(t) + " is not in the piece it comes from");
        return from.primitives[size_t(at - fromParticles.begin())].withGlobalIds(std::move(ids));
    });
}

geometry::FaceList LatticeBody::surfaceIn(const geometry::PhysicalMesh& mesh, const std::vector<int>& meshParticles,
                                          const std::vector<int>& particles) const {
    // Primitive i is tet meshParticles[i], its vertex k that tet's node k (physicalMesh).
    std::vector<int> idOf(lattice_.mesh().nodes.size(), -1);
    for (size_t i = 0; i < meshParticles.size(); ++i) {
        const lattice::Tet& tet = lattice_.mesh().tets[meshParticles[i]];
        for (int k = 0; k < 4; ++k) idOf[tet[k]] = mesh.primitives[i].globalIds()[k];
    }
    const std::vector<std::array<int, 3>> nodeFaces = lattice::surfaceFaces(lattice_, particles);
    geometry::FaceList faces;
    faces.reserve(nodeFaces.size(), 3 * nodeFaces.size());
    for (const auto& face : nodeFaces) {
        const std::array<int, 3> ids = {idOf[face[0]], idOf[face[1]], idOf[face[2]]};
        faces.add(ids);
    }
    return faces;
}

BodySettings LatticeBody::bodySettings(bool anchored) const {
    BodySettings b;
    b.rigidBody = settings_.rigidBody;
    b.dynamic = !anchored;
    return b;
}

} // namespace shatter
