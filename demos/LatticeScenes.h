#pragma once
// The breakable-body scenes (source 002 §4), shared by their demos (shatter-wall, -table,
// -noise) and by the benchmark (shatter-bench-lattice --scene): each scene's options with
// their command-line flags, and a builder that puts the scene into a demo Scene.
#include <shatter/bullet_ext/lattice/LatticeBody.h>
#include "demos/runner/Scene.h"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace shatter::demo {

struct Ball {
    double speed;  // m/s
    double mass;   // kg
    double radius; // m
};

// The demos' debris size (m): a piece of up to about four of the built-in walls' 10 cm cells
// (a lone tet of them is 0.14-0.19 m across), fragments of a glass top up to a hand's width.
constexpr double kDebrisSize = 0.25;

// What every lattice scene lets a user change.
struct LatticeOptions {
    std::string tets;          // a TetGen mesh (.ele with its .node) instead of the built-in one
    std::string material;      // a lattice::materialNamed preset
    double strength = 0.0;     // Pa, when given: instead of the material's
    double density = 0.0;      // kg/m³, when given: instead of the material's
    bool strengthGiven = false, densityGiven = false;
    double jitter = 0.0;       // node jitter of the built-in mesh, fraction of a cell
    bool spreading = true;     // dynamic weakening around breaks
    bool replay = true;        // replay impacts against the fragments
    bool freeze = true;        // freeze resting fragments
    std::string anchor = "bottom"; // --anchor: which tets are fixed (see setAnchor)
    double sliverQuality = lattice::kSliverQuality; // --sliver-quality: tets below it are bound to a neighbour
    // Debris (DebrisSettings): loose pieces up to --debris-size (m) do not collide with each
    // other and rest sooner; --debris-budget, --debris-lifetime, --debris-rest; --no-debris turns it off.
    double debrisSize = kDebrisSize;
    int debrisBudget = 0;
    double debrisLifetime = 0.0;
    double debrisRest = DebrisSettings{}.sleepAfter; // --debris-rest: s a debris piece stays put before it rests
    bool debris = true;
    double minFragmentSize = LatticeSettings{}.minFragmentSize; // --min-fragment-size (m)
    int fragmentBudget = LatticeSettings{}.fragmentBudget; // --fragment-budget: new bodies per body and step
    bool keepPairs = LatticeSettings{}.keepPairsOnShrink;   // --keep-pairs: a shrinking piece keeps its pairs
};

struct WallOptions {
    Ball ball{9.0, 400.0, 0.25};
    LatticeOptions lattice{"", "adobe", 0, 0, false, false, 0.15};
};

struct TableOptions {
    Ball ball{6.0, 8.0, 0.1}; // downward, from 0.4 m above the top
    LatticeOptions lattice{"", "glass", 0, 0, false, false, 0.1, true, true, true, "none"}; // rests on its legs
    double cleaving = 0.3;    // strength factor on the plane x = 0 (1 = no plane)
    // Half-width of the cleaving band in metres: the faces the plane cuts and those whose centre
    // lies within this distance of it are weakened. 5 mm = a quarter of the built-in 2 cm top's
    // thickness, the band the demo always had; a brought mesh keeps 5 mm whatever its height.
    double cleavingBand = 0.005;
    // A crack that reaches the plane runs along it (CleavingPlane::crackRuns): the top parts in
    // two along its middle, as in the source's Fig. 3; off, the ball makes a hole.
    bool crackRuns = true;
};

struct NoiseOptions {
    Ball ball{9.0, 300.0, 0.15};
    LatticeOptions lattice{"", "adobe", 0, 0, false, false, 0.0};
    double amplitude = 0.7; // noise amplitude
    double scale = 0.15;    // m, noise feature size
};

// --debris-size, --debris-budget, --debris-lifetime, --debris-rest, --no-debris and
// --min-fragment-size (every scene has them).
void addDebrisOptions(CLI::App& cli, LatticeOptions& o);
// --fragment-budget (LatticeSettings::fragmentBudget; every scene has it).
void addFragmentBudgetOption(CLI::App& cli, LatticeOptions& o);
// --keep-pairs (LatticeSettings::keepPairsOnShrink; every scene has it).
void addKeepPairsOption(CLI::App& cli, LatticeOptions& o);

// The scene's command-line options (what shatter-wall, -table and -noise take).
void addOptions(CLI::App& cli, WallOptions& o);
void addOptions(CLI::App& cli, TableOptions& o);
void addOptions(CLI::App& cli, NoiseOptions& o);

// Builds the scene into `scene` (ground, body or bodies, ball) and registers its summary keys;
// returns the breakable bodies. Throws shatter::InputError for bad options or meshes;
// `program` prefixes the mesh warnings printed on stderr.
std::vector<LatticeBody*> buildScene(Scene& scene, const WallOptions& o, const std::string& program);
std::vector<LatticeBody*> buildScene(Scene& scene, const TableOptions& o, const std::string& program);
std::vector<LatticeBody*> buildScene(Scene& scene, const NoiseOptions& o, const std::string& program);

// The fixed tets of `body` for an --anchor value in mesh coordinates (m, y up): "bottom" = the
// tets with a face on the mesh's lowest plane; "none"; "tets:I,J,..." = those tets (0-based);
// "below:H" = the tets whose centroid has y <= H; "box:x0,y0,z0,x1,y1,z1" = the tets whose
// centroid lies in that box. Throws shatter::InputError for a malformed value or an anchor that
// holds no tet (naming the body).
std::vector<int> anchorTets(const std::string& anchor, const lattice::TetMesh& mesh, const std::string& body);

// The anchors of `settings` for any --anchor value: those of anchorTets, and, resolved where
// the body is placed (LatticeSettings::anchorRegions, anchorTo), "world-below:H" and
// "world-box:..." (the same regions in world coordinates) and "contact" or "contact:D" (the
// tets within D m, 5 mm by default, of the scene's static `supports`: the ground, the legs).
void setAnchor(const std::string& anchor, const lattice::TetMesh& mesh, LatticeSettings& settings,
               const std::vector<const btCollisionObject*>& supports);

// The summary keys of a lattice demo for one breakable body (with `slivers` and
// `fragments_lone_sliver`: pieces that are a single sliver, none while they are bound).
nlohmann::json latticeCounts(const LatticeBody& b);

// Adds to the summary the fastest any piece of `bodies` moved in any frame (m/s, its centre of
// mass: fragment_speed_max, its frame and tets; its fastest point, spin included:
// fragment_point_speed_max) and the scene's mechanical energy (J: the bodies'
// pieces and the scene's dynamic rigid bodies, kinetic plus potential above y = 0) at the start,
// its most in any frame and at the end (energy_initial, energy_max, energy_final).
void trackMotion(Scene& scene, std::vector<LatticeBody*> bodies);
// That energy now.
double sceneEnergy(Scene& scene, const std::vector<LatticeBody*>& bodies);

} // namespace shatter::demo
