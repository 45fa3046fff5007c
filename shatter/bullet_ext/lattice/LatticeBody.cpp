#include <shatter/bullet_ext/lattice/LatticeBody.h>

#include <shatter/bullet_ext/VisualBody.h>
#include <shatter/plugin/common/InputError.h>
#include <shatter/plugin/lattice/Fragments.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <unordered_map>

namespace shatter {

namespace {

void requireRange(bool ok, const std::string& body, const std::string& what, double value) {
    if (ok) return;
    std::ostringstream msg;
    msg << body << ": " << what << ", got " << value;
    throw InputError(msg.str());
}

lattice::Lattice buildLattice(lattice::TetMesh mesh, const LatticeSettings& s) {
    if (mesh.name.empty() || mesh.name == "tet mesh") mesh.name = s.name;
    validateLatticeSettings(s, int(mesh.tets.size()));
    lattice::Lattice l(std::move(mesh), s.material);
    for (int t : s.fixedTets) l.setFixed(t, true);
    lattice::applyCleavingPlanes(l, s.cleavingPlanes);
    lattice::applyNoise(l, s.noise, s.seed);
    return l;
}

} // namespace

void validateLatticeSettings(const LatticeSettings& s, int tetCount) {
    const std::string& body = s.name;
    lattice::validateMaterial(s.material, body);
    lattice::validateBreakingSettings(s.fracture.breaking, body);
    lattice::validateDamageSpreading(s.fracture.spreading, body);
    lattice::validateCleavingPlanes(s.cleavingPlanes, body);
    lattice::validateNoiseSettings(s.noise, body);
    const auto& solver = s.fracture.solver;
    requireRange(solver.tolerance > 0.0 && solver.tolerance < 1.0, body, "solver tolerance must be in (0, 1)", solver.tolerance);
    requireRange(solver.maxIterations >= 1, body, "solver max iterations must be >= 1", solver.maxIterations);
    requireRange(s.impactParticles >= 1, body, "impact particles must be >= 1", s.impactParticles);
    requireRange(std::isfinite(s.reanalysisFraction) && s.reanalysisFraction >= 0, body,
                 "reanalysis fraction must be >= 0 and finite", s.reanalysisFraction);
    requireRange(s.maxRotationPerStep > 0, body, "max rotation per step must be > 0 rad", s.maxRotationPerStep);
    requireRange(std::isfinite(s.friction) && s.friction >= 0, body, "friction must be >= 0 and finite", s.friction);
    requireRange(std::isfinite(s.restitution) && s.restitution >= 0, body, "restitution must be >= 0 and finite", s.restitution);
    requireRange(std::isfinite(s.collisionMargin) && s.collisionMargin >= 0, body, "collision margin must be >= 0 m",
                 s.collisionMargin);
    requireRange(std::isfinite(s.convexHullTolerance) && s.convexHullTolerance >= 0, body,
                 "convex hull tolerance must be >= 0 and finite", s.convexHullTolerance);
    requireRange(std::isfinite(s.sleepAfter) && s.sleepAfter >= 0, body, "sleep after must be >= 0 s and finite",
                 s.sleepAfter);
    requireRange(std::isfinite(s.sleepDrift) && s.sleepDrift >= 0, body, "sleep drift must be >= 0 m and finite",
                 s.sleepDrift);
    requireRange(std::isfinite(s.sleepTurn) && s.sleepTurn >= 0, body, "sleep turn must be >= 0 rad and finite",
                 s.sleepTurn);
    requireRange(std::isfinite(s.wakeSpeed) && s.wakeSpeed >= 0, body, "wake speed must be >= 0 m/s and finite", s.wakeSpeed);
    requireRange(std::isfinite(s.wakeDrift) && s.wakeDrift >= 0, body, "wake drift must be >= 0 m and finite", s.wakeDrift);
    requireRange(std::isfinite(s.linearDamping) && s.linearDamping >= 0, body, "linear damping must be >= 0", s.linearDamping);
    requireRange(std::isfinite(s.angularDamping) && s.angularDamping >= 0, body, "angular damping must be >= 0",
                 s.angularDamping);
    for (int t : s.fixedTets)
        requireRange(t >= 0 && t < tetCount, body,
                     "fixed tet index out of range (the mesh has " + std::to_string(tetCount) + " tets)", t);
}

LatticeBody::LatticeBody(int id, lattice::TetMesh mesh, const LatticeSettings& settings)
    : id_(id), settings_(settings), lattice_(buildLattice(std::move(mesh), settings)), random_(settings.seed) {}

const lattice::NearestParticles& LatticeBody::Piece::nearestParticles(const lattice::Lattice& l) {
    if (!nearest) {
        std::vector<Eigen::Vector3d> points;
        points.reserve(lattice.particles.size());
        for (int p : lattice.particles) points.push_back(l.particles()[p].position);
        nearest = std::make_shared<lattice::NearestParticles>(std::move(points));
    }
    return *nearest;
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

geometry::PhysicalMesh LatticeBody::physicalMesh(const std::vector<int>& particles, const std::string& name) const {
    const lattice::TetMesh& mesh = lattice_.mesh();
    geometry::PhysicalMesh out;
    out.name = name;
    // Nodes renumbered compactly per piece, so each piece's visual mesh holds only its own.
    std::unordered_map<int, int> local;
    auto localId = [&](int node) {
        const auto [it, inserted] = local.emplace(node, int(out.visual.positions.size()));
        if (inserted) out.visual.positions.push_back(mesh.nodes[node]);
        return it->second;
    };
    static const std::vector<std::vector<int>> kFaces = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
    out.primitives.reserve(particles.size());
    for (int t : particles) {
        const lattice::Tet& tet = mesh.tets[t];
        std::vector<Eigen::Vector3d> corners;
        std::vector<int> ids;
        for (int n : tet) {
            corners.push_back(mesh.nodes[n]);
            ids.push_back(localId(n));
        }
        out.primitives.push_back(geometry::ConvexPolyhedron::create(std::move(corners), kFaces, std::move(ids),
                                                                    name + " tet " + std::to_string(t)));
        out.sourceFace.push_back(-1);
    }
    for (const auto& face : lattice::surfaceFaces(lattice_, particles))
        out.visual.faces.push_back({localId(face[0]), localId(face[1]), localId(face[2])});
    out.globalIdCount = int(out.visual.positions.size());
    out.mass = lattice::pieceMassProperties(lattice_, particles);
    out.density = lattice_.material().density;
    return out;
}

std::vector<std::vector<int>> LatticeBody::surfaceIn(const geometry::PhysicalMesh& mesh,
                                                     const std::vector<int>& meshParticles,
                                                     const std::vector<int>& particles) const {
    // Primitive i is tet meshParticles[i], its vertex k that tet's node k (physicalMesh).
    std::vector<int> idOf(lattice_.mesh().nodes.size(), -1);
    for (size_t i = 0; i < meshParticles.size(); ++i) {
        const lattice::Tet& tet = lattice_.mesh().tets[meshParticles[i]];
        for (int k = 0; k < 4; ++k) idOf[tet[k]] = mesh.primitives[i].globalIds()[k];
    }
    std::vector<std::vector<int>> faces;
    for (const auto& face : lattice::surfaceFaces(lattice_, particles))
        faces.push_back({idOf[face[0]], idOf[face[1]], idOf[face[2]]});
    return faces;
}

BodySettings LatticeBody::bodySettings(bool anchored) const {
    BodySettings b;
    b.mesh.density = lattice_.material().density;
    b.friction = settings_.friction;
    b.restitution = settings_.restitution;
    b.collisionMargin = settings_.collisionMargin;
    b.dynamic = !anchored;
    b.linearDamping = settings_.linearDamping;
    b.angularDamping = settings_.angularDamping;
    return b;
}

} // namespace shatter
