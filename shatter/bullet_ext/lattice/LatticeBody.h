#pragma once
// A breakable body in a Bullet world (source 002): the lattice of its tet mesh and the pieces
// it is in now. Unbroken, it is one rigid body (one piece); every break that cuts a piece in
// two or more makes each part a new rigid body with the part's own mass, centre of mass and
// inertia, moving as the piece moved at that point (except an anchored piece's largest part,
// when it keeps most of the tets: it keeps the static body and sheds the tets that left).
// Each piece's Bullet body is a VisualBody (owned by the Plugin) whose group shape holds the
// piece's tets as convex polyhedra and whose visual mesh is the piece's surface: outer faces
// and crack faces. A convex piece (every single tet among them) collides as its convex hull
// instead (shape/FragmentHull.h).
#include <shatter/bullet_ext/BodySettings.h>
#include <shatter/bullet_ext/lattice/FrozenBody.h>
#include <shatter/bullet_ext/lattice/LatticeSettings.h>
#include <shatter/plugin/geometry/PhysicalMesh.h>
#include <shatter/plugin/lattice/Lattice.h>
#include <shatter/plugin/lattice/LatticePiece.h>
#include <shatter/plugin/lattice/Random.h>
#include <shatter/plugin/lattice/Slivers.h>

#include <BulletCollision/CollisionShapes/btConvexHullShape.h>

#include <memory>
#include <string>
#include <vector>

namespace shatter {

class VisualBody;

class LatticeBody {
public:
    struct Piece {
        lattice::LatticePiece lattice;      // its particles and solver state
        VisualBody* body = nullptr;         // its Bullet body (owned by the Plugin)
        geometry::MassProperties mass;      // exact, mesh coordinates
        // Its collision shape when the piece is convex (then the body's group shape only
        // carries the visual mesh), else null.
        std::unique_ptr<btConvexHullShape> hull;
        // Rest detection (LatticeSettings::sleepAfter): where the body was when it last moved
        // more than the drift or turn, and for how long (s) it has stayed near there.
        btTransform restPose = btTransform::getIdentity();
        double restFor = 0.0;
        // While frozen (LatticeSettings::freezeAtRest) the body is static; `frozenAs` restores
        // it. `supports`: what it leaned or lay on when it froze (not bodies fixed for good),
        // and where they were then.
        bool frozen = false;
        FrozenBody frozenAs;
        struct Support {
            const btCollisionObject* body;
            btVector3 origin;
        };
        std::vector<Support> supports;
        // Debris (LatticeSettings::debris): a small loose piece, and when it was made (s).
        bool debris = false;
        double madeAt = 0.0;
        // It still holds parts that have come apart, left in it by the fragment budget
        // (LatticeSettings::fragmentBudget): it splits again next step, and never rests before.
        bool splitPending = false;
    };

    // Builds the lattice and applies fixed tets, cleaving planes, noise and the binding of
    // slivers (LatticeSettings::sliverQuality). Anchors by region or body must have been
    // resolved into fixedTets (resolveAnchors). Throws shatter::InputError naming the body for a
    // bad mesh or bad settings.
    LatticeBody(int id, lattice::TetMesh mesh, const LatticeSettings& settings);

    int id() const { return id_; }
    const std::string& name() const { return settings_.name; }
    const LatticeSettings& settings() const { return settings_; }
    const lattice::Lattice& lattice() const { return lattice_; }
    const std::vector<Piece>& pieces() const { return pieces_; }

    int tetCount() const { return lattice_.particleCount(); }
    int linkCount() const { return lattice_.linkCount(); }
    int brokenLinkCount() const { return lattice_.brokenCount(); }
    int pieceCount() const { return int(pieces_.size()); }
    int frozenPieceCount() const; // resting pieces frozen as static bodies (LatticeSettings::freezeAtRest)
    double initialMass() const { return lattice_.totalMass(); } // kg, before any break
    double currentMass() const;                                 // kg, summed over the pieces
    // kg of the debris pieces removed (DebrisSettings::lifetime, budget): initialMass() is
    // currentMass() plus this, unless the application removed pieces itself.
    double removedDebrisMass() const { return removedDebrisMass_; }
    int removedDebrisCount() const { return removedDebris_; }
    int sliverCount() const { return slivers_.slivers; }        // tets below settings().sliverQuality
    int boundLinkCount() const { return int(slivers_.links.size()); } // links that bind them (unbreakable)
    // Kinetic energy of every piece plus its potential energy in `gravity` (zero at the world
    // origin), J: anchored and frozen pieces count with their mass at rest.
    double mechanicalEnergy(const btVector3& gravity) const;
    // The fastest loose piece now: its centre of mass's speed (m/s) and tets; and the fastest
    // any point of any piece moves (its centre of mass's speed plus its spin times its bounding
    // radius).
    struct Speeds {
        double centre = 0.0;
        int tets = 0;
        double point = 0.0;
    };
    Speeds fastestPieces() const;

    // For LatticeSystem.
    lattice::Lattice& mutableLattice() { return lattice_; }
    std::vector<Piece>& mutablePieces() { return pieces_; }
    lattice::Random& random() { return random_; }
    // The physical mesh of a set of tets (mesh coordinates): one tetrahedron primitive per
    // tet, the visual surface of the set, exact mass properties.
    geometry::PhysicalMesh physicalMesh(const std::vector<int>& particles, const std::string& name) const;
    // The same for `particles` (sorted), a part of a piece whose physical mesh is `from` over
    // `fromParticles` (sorted, a superset): each tet's primitive is a copy of its primitive
    // there with the new vertex ids, the same bits as building it again (a new fragment's
    // build was most of a break frame's fragment work).
    geometry::PhysicalMesh partMesh(const geometry::PhysicalMesh& from, const std::vector<int>& fromParticles,
                                    const std::vector<int>& particles, const std::string& name) const;
    // The visual surface of `particles` (outer and crack faces) in the visual vertex ids of
    // `mesh`, the physical mesh of a piece over `meshParticles` (a superset): for a piece that
    // sheds tets and keeps its body, whose primitives keep their vertex ids. In one flat list:
    // a vector per face was 61k allocations (11.5 M instructions) at three shrinks of the
    // 55k-tet Spot statue.
    geometry::FaceList surfaceIn(const geometry::PhysicalMesh& mesh, const std::vector<int>& meshParticles,
                                 const std::vector<int>& particles) const;
    // Exact mass properties of a set of tets (mesh coordinates), from each tet's kept ones.
    geometry::MassProperties massOf(const std::vector<int>& particles) const;
    BodySettings bodySettings(bool anchored) const;
    std::string nextPieceName();
    void noteDebrisRemoved(double mass) { removedDebrisMass_ += mass, ++removedDebris_; }

private:
    // physicalMesh's and partMesh's common part: primitive(t, ids) is tet t's primitive with
    // vertex ids `ids` (its nodes' compact numbers in this mesh).
    template <typename Primitive>
    geometry::PhysicalMesh meshOf(const std::vector<int>& particles, const std::string& name,
                                  const Primitive& primitive) const;

    int id_;
    LatticeSettings settings_;
    lattice::Lattice lattice_;
    std::vector<Piece> pieces_;
    lattice::Random random_;
    lattice::SliverBinding slivers_;
    // Each tet's mass properties (112 bytes a tet): the anchored rest's are summed again after
    // every break, and computing them was most of that sum.
    std::vector<geometry::MassProperties> tetMass_;
    // meshOf's node numbers (-1 between its calls), kept so that a call touches only its nodes.
    // So physicalMesh and partMesh, though const, must not run on one body on two threads at once.
    mutable std::vector<int> localNode_;
    int piecesMade_ = 0;
    double removedDebrisMass_ = 0.0;
    int removedDebris_ = 0;
};

// Kinetic energy of a rigid body (J), linear and rotational; 0 for a static one.
double kineticEnergy(const btRigidBody& body);

// The name a body's mesh goes by in messages: its own, or the body's when it has none.
std::string meshNameFor(const lattice::TetMesh& mesh, const LatticeSettings& settings);

} // namespace shatter
