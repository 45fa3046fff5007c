#pragma once
// How a tet mesh becomes a breakable Bullet body (source 002). Units SI; every default gives a
// plausible scene.
#include <shatter/bullet_ext/BodySettings.h>
#include <shatter/plugin/lattice/AnchorRegion.h>
#include <shatter/plugin/lattice/CleavingPlane.h>
#include <shatter/plugin/lattice/FractureAnalysis.h>
#include <shatter/plugin/lattice/MaterialSettings.h>
#include <shatter/plugin/lattice/Noise.h>
#include <shatter/plugin/lattice/Slivers.h>

#include <BulletCollision/CollisionDispatch/btCollisionObject.h>

#include <cstdint>
#include <string>
#include <vector>

namespace shatter {

// When loose pieces of a lattice body rest (RestingPieces.h).
struct RestSettings {
    // A loose piece whose centre of mass has stayed within `sleepDrift` (m) and whose
    // orientation within `sleepTurn` (rad) of where they were `sleepAfter` (s) ago (on
    // average slower than 5 cm/s and 0.5 rad/s) is resting. Bullet's own rule (below its
    // velocity thresholds for 2 s) restarts on every momentary spin a contact gives a tet in
    // a heap; where the piece is does not. A resting piece is made ready to sleep (Bullet's
    // deactivation timer is set past gDeactivationTime), and frozen (below).
    double sleepAfter = 0.1;
    double sleepDrift = 0.005;
    double sleepTurn = 0.05;
    // Freezing (FrozenBody.h). Bullet sleeps a body only with its whole island, and an
    // island is every body whose box overlaps another's, transitively: the crater and heap of
    // the wall benchmark (270-480 loose tets, 20,000-60,000 box pairs) stayed one island,
    // awake through its 4 s because a few pieces kept sliding, and its narrowphase was most
    // of every frame. With `freezeAtRest`, a resting piece that is below Bullet's sleeping
    // thresholds right now becomes a static body: it leaves the islands and its pairs with
    // static bodies and other frozen pieces. It wakes (a dynamic body again, with its own
    // mass and inertia, at rest) when
    // - a dynamic body hits it: a point of the body touching it approached it faster than
    //   `wakeSpeed` (m/s) at the start of the step. That step met the body with a static
    //   one; its contact impulses are taken back, so the next step meets it with the piece's
    //   own mass. A body pushing slower than `wakeSpeed` meets a static piece;
    // - something it leaned or lay on when it froze (another frozen piece, a loose piece, an
    //   application's body; not the ground or an anchored part) has moved by more than
    //   `wakeDrift` (m) or left the world: a frozen piece floats at most that far;
    // - a part breaks off an anchored piece (which is not watched as a support) where the
    //   part's box overlaps it;
    // - a moving kinematic body's box overlaps it (Bullet pairs no kinematic and static bodies);
    // - the application calls LatticeSystem::thaw (before pushing it, say).
    // A dynamic body lighter than `wakeMassRatio` times the frozen piece's mass neither wakes
    // it by a hit nor counts as its support. Such a hit could give the piece at most
    // 2·ratio/(1 + ratio) of its approach speed (4% at 0.02): the shard bounces off as off a
    // static body. Such a support, if the piece rested on it, would be pinned by its weight: a
    // shard that moves 2 cm was not holding the piece up. In the table benchmark (seed 1) the
    // broken halves (18-19 kg) were woken, after they had come to rest, by 11-259 g shards
    // (0.06-1.4% of their mass) hitting them at 0.2-0.26 m/s or sliding 2.1-2.2 cm past
    // them, five times; each time a half moved less than 3 mm and froze again 0.1 s later,
    // but while awake its ~39,000 leaf pairs with the other half cost 15-30 ms a frame.
    // 0 (any body wakes it): the rule before.
    bool freezeAtRest = true;
    double wakeSpeed = 0.2;
    double wakeDrift = 0.02;
    double wakeMassRatio = 0.02;

    void check(const std::string& body) const;
};

// Debris: the small loose pieces of a break. A game shows them but need not let every one of
// them collide with every other: in the frames after a break hundreds of fresh tets fly and
// land in one heap, each tet's box overlapping some 40 others, and their pairs and contacts
// were most of the frame (the wall benchmark, seed 1, its worst frame: 16,474 pairs, Bullet's
// narrowphase 79 ms and its solver 32 ms of the frame's 144 ms of CPU). Debris collide with the
// world's static bodies, the anchored parts, the pieces that are not debris and the
// application's bodies, never with each other: their pairs never reach the narrowphase
// (Bullet's broadphase filter: debris are in btBroadphaseProxy::DebrisFilter and leave it out
// of their mask). Off by default (maxSize 0); the lattice demos and benchmark turn it on
// (--debris-size, --no-debris).
struct DebrisSettings {
    // A loose fragment is debris when its size (m) is at most this: the diameter of the sphere
    // about its centre of mass that holds all its nodes (lattice::pieceSize), so a flat shard
    // counts by its width. Decided when a split makes the fragment (a body as the application
    // added it is never debris); 0: no debris.
    double maxSize = 0.0;
    bool collideWithEachOther = false;
    // Debris rest sooner: a debris piece touching something that has stayed within
    // RestSettings::sleepDrift and sleepTurn for this long (s), instead of
    // RestSettings::sleepAfter, sleeps and freezes (slower than 0.1 m/s over 12 steps of 1/240 s).
    // Measured on the wall benchmark, seeds 1-8, thread CPU summed over all frames: 0.05 s
    // 25.0 s (pieces awake 122,000 piece-frames), 0.025 s 19.2 s (76,000); 0.1 s (before
    // pieces in flight were kept from resting) 38.3 s (189,000).
    // 0.025 s is not the default: the table benchmark's top then broke into 479 fragments
    // instead of 156 (a half that fell on the shards shattered).
    double sleepAfter = 0.05;
    // s a debris piece lives before it is removed (0: for ever).
    double lifetime = 0.0;
    // Most debris pieces of the body alive at once; beyond it the oldest are removed first
    // (0: no limit). Every removal pushes EventType::DebrisExpired (count = the piece's tets)
    // before the body leaves the world, and adds the piece's mass to
    // LatticeBody::removedDebrisMass().
    int budget = 0;

    void check(const std::string& body) const;
};

struct LatticeSettings {
    std::string name = "lattice";
    lattice::MaterialSettings material;                          // density (kg/m³), strength (Pa); adobe by default
    lattice::FractureAnalysisSettings analysis;          // solver tolerance, breaking, damage spreading
    std::vector<lattice::CleavingPlane> cleavingPlanes;  // mesh coordinates
    lattice::NoiseSettings noise;                        // off by default
    // Anchored tets (infinite mass): the union of an explicit list, the tets whose centroid lies
    // in each region (mesh or world coordinates: lattice::AnchorRegion::frame; world = where the
    // body is created) and the tets within `anchorDistance` (m) of each body of `anchorTo`
    // (static Bullet bodies of the world, at creation: the ground a statue stands on, the legs
    // under a table top). A region or a body that anchors no tet is an error naming the body.
    std::vector<int> fixedTets;
    std::vector<lattice::AnchorRegion> anchorRegions;
    std::vector<const btCollisionObject*> anchorTo;
    double anchorDistance = 0.001;
    // Tets of quality (lattice::tetQuality) below this are bound to their best neighbour and
    // never break off alone (lattice::bindSlivers); 0 = none.
    double sliverQuality = lattice::kSliverQuality;
    // Smallest loose piece (m, lattice::pieceSize: the diameter about its centre of mass): when
    // the body breaks, smaller parts are merged with the small parts next to them into pieces
    // of at least this size, or stay with their neighbour, and the links that held them are
    // joined for good (lattice::fragmentParts, FragmentClusters.h). Without it a hit makes
    // about 2% of the tets around the crater into single-tet fragments, so the count grows with
    // the mesh's resolution. 0: none (single tets come loose).
    double minFragmentSize = 0.05;
    std::uint64_t seed = 1;                              // noise and damage spreading

    // An impact's force (contact impulse over the step) goes to this many particles nearest
    // to the contact point, weighted by inverse distance: up to 5 are taken among the touched
    // tet and its face neighbours (what Bullet's contact names), more from a grid search.
    int impactParticles = 4;
    // After a body breaks, the impulses of its contacts on parts that came loose are taken
    // back from both bodies (static ones are not moved), so that the next step's contact
    // solve meets the fragments with their own masses instead of the unbroken body's: a ball
    // is not stopped dead by a wall that has just shattered, and a table top that breaks is
    // not left with the push its legs gave against the ball. A moving piece that loses one
    // impulse loses all of the step's, and so do the moving bodies it touches (its contact
    // island): they leave the step with the motion they came in with, and none keeps an
    // unbalanced part of the step's contact forces (LatticeSystem::replayImpacts). A body
    // that is no piece (the ball) keeps its contacts with static bodies, the part of a wall
    // that stays anchored among them: they did stop it.
    bool replayImpacts = true;
    // A piece is analysed again only when the load on one of its particles has changed, since
    // its last analysis, by more than this fraction of the strength of that particle's weakest
    // link. A link carries mostly the loads of its own two particles (forces fall off by about
    // 3 per link away from a load), so smaller changes leave every link's force within about
    // this fraction of where it was; resting and jittering pieces then cost next to nothing.
    double reanalysisFraction = 0.1;

    // Largest rotation of a piece per internal step (rad), enforced by scaling its angular
    // velocity down after each step. Single-tet fragments have tiny moments of inertia, and
    // a contact on one can spin it up by hundreds of rad/s in a step; beyond a fraction of a
    // radian per step Bullet's contacts on the spinning piece feed energy back into it
    // (measured on the table demo: 17,000 rad/s and 47 m/s within a second). Only takes
    // energy away (and angular momentum: this is the one place it is not conserved).
    double maxRotationPerStep = 0.25;
    // Largest speed a piece in contact may leave a step with, as a multiple of the fastest
    // point of anything touching it at the start of the step (or its own speed then plus
    // gravity's gain, if more). A collision can at most double the approach speed of what hit
    // it (an elastic hit by a much heavier body), but Bullet's sequential-impulse solver, not
    // converged in its 10 iterations on a light fragment squeezed between heavy bodies (a
    // 14 g tet under the table demo's 8 kg ball: mass ratio 570), can give it far more, and
    // that energy spreads through the heap (measured on the table demo: pieces at 1,200 m/s
    // and 350 kJ of kinetic energy from a 144 J ball). Only takes energy away (and momentum:
    // the other place it is not conserved).
    double hitSpeedFactor = 2.0;

    // Every piece's Bullet body. The collision margin is half a visual body's: fragments start
    // touching face to face, so a margin makes them overlap by twice its size (resolved by split
    // impulses, without added velocity when the world's split-impulse threshold is 0); without
    // one, sliver tets caught between a heavy body and the rest get flung out (measured on the
    // table demo).
    RigidBodySettings rigidBody{.collisionMargin = 0.0005};
    // A piece collides as its convex hull (Bullet's own convex algorithms, cheaper than the
    // group shape's) when it is convex: a single tet always, a piece of up to
    // `convexHullMaxTets` tets when no node lies more than `convexHullTolerance` times the
    // edge of a cube of its volume in front of one of its surface faces (see
    // lattice::isConvexPiece; the hull then overfills it by a sliver at most that thin).
    // Mass, centre of mass and inertia are always the exact ones of the tets.
    double convexHullTolerance = 0.02;
    int convexHullMaxTets = 64;
    // Most new fragment bodies a body makes in one internal step (0: no limit). A new body
    // costs Bullet and the lattice most in the steps a wall shatters (30-120 parts a step on
    // the wall benchmark). A split that would make more makes the first parts (in the order
    // lattice::connectedComponents gives them); the others stay together: in a loose piece's
    // body (with its largest part), carried with its motion, or, for a static piece or a convex
    // one (its own hull shape), in one more new body (a static piece would hold them still
    // against what hit them). Such a piece is not analysed (its parts'
    // loads are not the clump's) and splits again in the next steps, within the budget, with
    // its motion then; mass and momentum are carried exactly as in any split. A split with no
    // budget left this step waits whole. 0 (no limit) or at least 2 (one part and the rest).
    // Off by default: on the wall benchmark (seed 6, 891 fragments without; solver tolerance
    // 1e-6) a budget of 16 made 2,517 fragments and 32 made 2,851, and both were slower: the
    // clumps of waiting parts are heavier than their parts, and what they hit breaks more.
    int fragmentBudget = 0;
    // A split piece's part that keeps the piece's body loses the other parts' primitives
    // (LatticeSystem::shrinkPiece). False (the default): the body leaves the world while its shape
    // shrinks, as for any change of shape, and every pair of it is made anew at the next step: each
    // leaf pair of two groups listed and clipped fresh, its manifold made again (the table
    // benchmark's halves: tens of thousands of leaf pairs at every shrink). True: the body stays
    // in the world and its pairs keep their leaf pairs and manifolds, the ones on removed
    // primitives dropped and the points re-based to the body's new centre of mass
    // (SystemContext::removeInWorld). The contacts then keep their warm start and their places in
    // Bullet's lists, and so the chaotic scenes break otherwise. A moving body's first shrink,
    // while it still collides as its bare group shape, leaves the world either way (a static
    // piece is never reframed: it keeps its pairs from its first shrink on).
    bool keepPairsOnShrink = false;
    RestSettings rest;     // when loose pieces sleep and freeze, and when frozen ones wake
    DebrisSettings debris; // which pieces are debris and what becomes of them

    // Every field in range; a fixed tet must be one of the mesh's `tetCount`. Names the body by `name`.
    void check(int tetCount) const;
};

} // namespace shatter
