#pragma once
// When and how a visual body shatters (source 000 §2.3, §3.6): a fracture pattern, a connected
// set of convex cells, is placed where a contact struck harder than `threshold`, and every
// cell within `radius` of the hit cuts a fragment free. Off by default. Units SI.
#include <cstdint>
#include <string>

namespace shatter {

enum class PatternKind {
    Voronoi, // 3D Voronoi cells, small near the impact and growing outward (solids)
    Glass,   // radial sectors times rings (thin sheets: a hole and radial shards)
    Grid,    // a jittered regular grid
    File,    // the convex cells of `patternFile` (one OBJ object per cell)
};

// "voronoi", "glass", "grid"; throws shatter::InputError listing them for anything else.
PatternKind patternKindNamed(const std::string& name);
const char* toString(PatternKind kind);

struct FractureSettings {
    bool enabled = false;
    PatternKind pattern = PatternKind::Voronoi;
    std::string patternFile; // PatternKind::File: an OBJ of closed convex cells, in metres
    int cells = 64;          // cells of a generated pattern
    // Contact impulse (N·s, summed over the points of one contact pair in one step) above
    // which the body breaks at that contact. 2 N·s: a 1 kg vase landing at about 2 m/s.
    double threshold = 2.0;
    // Only cells within this distance of the impact cut fragments free (m); the rest of the
    // body stays one piece (or one per island the cut left).
    double radius = 0.3;
    // Pieces smaller than this (m, the cube root of their volume) are merged into a neighbour
    // of their cell, never dropped.
    double minimumPieceSize = 0.004;
    // How many more times the fragments may break again (0: fragments never break).
    int depth = 1;
    // A body made by a fracture does not break again for this long (s): the contacts of the
    // step it broke in are still pushing its pieces.
    double coolDown = 0.1;
    std::uint64_t seed = 1; // the pattern's sites and twist: same seed, same pieces

    // Cells >= 1, threshold, radius and minimum piece size positive, depth >= 0, cool-down
    // >= 0, all finite; a file pattern names a file. Checked only when enabled.
    void check(const std::string& body) const;
};

} // namespace shatter
