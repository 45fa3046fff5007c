#pragma once
// When and how a visual body shatters (source 000 §2.3, §3.6): a fracture pattern, a connected
// set of convex cells, is placed where a contact struck harder than `threshold`, and every
// cell within `radius` of the impact cuts a fragment free. Off by default. Units SI.
#include <shatter/plugin/fracture/FracturePattern.h>

#include <cstdint>
#include <string>

namespace shatter {

enum class PatternKind {
    Voronoi, // 3D Voronoi cells, small near the impact and growing outward (solids)
    Glass,   // radial sectors times rings through a thin sheet (a hole and radial shards)
    Grid,    // a jittered regular grid
    File,    // the convex cells of `patternFile` (one OBJ object per cell)
};

// "voronoi", "glass", "grid"; throws shatter::InputError listing them for anything else.
PatternKind patternKindNamed(const std::string& name);
const char* toString(PatternKind kind);

// What a hit above the threshold does with the pattern's cuts (source 000 §3.6).
enum class FractureMode {
    Shatter,   // brittle: the cells within the radius become separate bodies (deformation None)
    Subdivide, // ductile / adaptive detail: the cut primitives stay one body, in place, so a
               // plastic body dents with detail where hit (deformation None or Plastic)
};
// "shatter", "subdivide"; throws shatter::InputError listing them for anything else.
FractureMode fractureModeNamed(const std::string& name);
const char* toString(FractureMode mode);

struct FractureSettings {
    bool enabled = false;
    FractureMode mode = FractureMode::Shatter;
    PatternKind pattern = PatternKind::Voronoi;
    // The pattern of each kind, in metres with the impact at the origin and +z into the body
    // (plugin/fracture/FracturePattern.h). Their own radius is replaced by `radius` below.
    fracture::VoronoiPatternSettings voronoi;
    fracture::GlassPatternSettings glass;
    fracture::GridPatternSettings grid;
    std::string patternFile; // PatternKind::File: an OBJ of closed convex cells, in metres
    // Contact impulse (N·s, summed over the points of one contact pair in one step) above
    // which the body breaks at that contact.
    double threshold = 2.0;
    // Only cells whose centre is within this distance (m) of the impact cut fragments free;
    // the rest of the body stays together (one body per island the cut left).
    double radius = 0.3;
    // A fragment smaller than this (m, the cube root of its volume) joins a neighbour: nothing
    // is dropped.
    double minimumPieceSize = 0.005;
    // m. A fragment whose hull overlaps no other piece (FractureResult::hullIsClear) whose bounding box has a
    // diagonal below this collides as the convex hull of its pieces instead of a group shape
    // of them. A heap of shards then costs Bullet a hull pair per touching pair of shards,
    // not a test per pair of their primitives. The hull lies in the fragment's cell, so it
    // overlaps no other fragment nor the rest: nothing is pushed apart at the break. The
    // price is the fragment's concave side: a curved shard rests on its chord. Its mass,
    // centre of mass and inertia stay its pieces'. 0: only one-primitive fragments are hulls.
    double hullBelow = 0.0;
    // Shatter: how many more times fragments may break again (0: fragments never break).
    // Subdivide: how many more times the body may be subdivided after its first subdivision.
    int depth = 1;
    // A body made by a fracture does not break for this long (s): the contacts of the step
    // its parent broke in are still pushing it. Also the wait after a hit that cut nothing.
    double coolDown = 0.1;
    // World steps after a break in which the bodies of that break (its fragments and the rest)
    // do not collide with each other; they still collide with everything else. They are created
    // touching along every crack face and moving as the parent did, so in those steps their
    // contacts would only hold them together as the intact body did, yet their first contacts
    // cost as much as the break itself (the vase: about 30 M instructions a step for its
    // shards). The pause moves that cost out of the step that broke them and the next ones.
    // Nothing holds the pieces together meanwhile: pieces the floor stops and pieces above
    // them drift into each other by about g (n dt)² / 2 (0.8 mm for 3 steps of 1/240 s), which
    // their contacts then undo without adding energy (Bullet's split impulse). Keep it to a
    // few steps: after 24 (0.1 s) a landing block's pieces had sunk 3 cm into each other and
    // their contacts threw them apart with 6 J (FractureSystem tests). 0: they collide from
    // the first step.
    int contactDelaySteps = 0;
    // World steps between fracture events (a budget of one event per this many steps, for the
    // whole world): a hit above the threshold that comes sooner after the world's last event
    // is kept, its point and direction in the body's rest coordinates, and the body breaks
    // there at the first step the budget allows, with its motion of then (mass and momenta
    // are conserved at that event as at any). Two bodies landing in the same step then break
    // in different frames when this is the frame's step count (the vase and the bowl: 4).
    // Kept hits go before fresh ones, in the order the bodies were added. A scripted break
    // (Plugin::fracture) never waits, but counts, as does a subdivision. 0: no budget.
    int eventSpacingSteps = 0;
    std::uint64_t seed = 1; // the pattern's sites and twist: same seed, same pieces

    // Sets the cell count of every generated kind: Voronoi sites, glass sectors × rings (about
    // `cells`, rings ≈ √(cells/3)), grid count³ (about `cells`).
    void setCells(int cells);
    // The pattern these settings make, with `radius` (throws shatter::InputError naming `body`
    // for bad pattern settings or a bad pattern file).
    fracture::FracturePattern makePattern(const std::string& body) const;

    // Mode one of the enum's, threshold, radius and minimum piece size positive, depth >= 0,
    // cool-down >= 0, hullBelow >= 0, contactDelaySteps >= 0, eventSpacingSteps >= 0, all finite, the pattern kind's own settings valid; a file pattern names a
    // file. Checked only when enabled. (Which deformation goes with which mode: BodySettings.)
    void check(const std::string& body) const;
};

} // namespace shatter
