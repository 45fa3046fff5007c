#pragma once
// A fracture pattern (source 000 §3.6, after Müller et al. 2013): a connected set of convex
// cells in its own coordinates, built once and placed at every impact. The impact is at the
// origin and the pattern's axis +z points into the body (along the impact direction).
#include <shatter/plugin/geometry/ConvexPolyhedron.h>
#include <shatter/plugin/geometry/ObjFile.h>

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

namespace shatter::fracture {

// A face of a cell on one of the pattern's shared planes: the cell lies on the negative
// side of sign·(n·x − d). Neighbouring cells refer to the same plane with opposite signs, so
// a primitive cut from both sides gets bit-identical crack vertices.
struct CellFace {
    int plane = 0;
    double sign = 1.0;
};

struct FracturePattern {
    std::vector<geometry::ConvexPolyhedron> cells;
    // Cells whose centre lies within this distance of the origin (pattern units, so scaled
    // with the placement) cut pieces free; the rest of the body keeps everything else.
    double radius = 0.0;
    // Per cell: the point whose distance to the origin decides whether it is within the
    // radius (the Voronoi site; the centroid for cells from a file). Filled by finishPattern.
    std::vector<Eigen::Vector3d> centres;
    // The distinct planes of all cells, and per cell its faces on them (finishPattern).
    std::vector<geometry::Plane> planes;
    std::vector<std::vector<CellFace>> cellFaces;
    // The faces of the convex region the cells fill, on the shared planes: set by the
    // patterns that know it (Voronoi cells in their box: setBoxDomain), empty otherwise
    // (cells from a file, or edited by hand). What a cut leaves of a primitive beyond the
    // pattern is then the primitive less this one region, not less every cell that cut it.
    std::vector<CellFace> domain;
};

// Fills centres (centroids where `centres` is empty) and the shared planes: cell face planes
// within `tolerance` (pattern units) of each other, either way round, become one plane.
// Clears the domain (its plane indices are the old ones).
// Every pattern function calls it; call it again after editing cells by hand.
void finishPattern(FracturePattern& pattern, double tolerance = 1e-9);

// For cells that fill `box` (a Voronoi diagram bounded by it): the domain is the box, its
// walls found among the shared planes (within `tolerance`). Left empty when a wall is on no
// cell's face.
void setBoxDomain(FracturePattern& pattern, const geometry::Aabb& box, double tolerance = 1e-9);

// Throws shatter::InputError naming `what` for a pattern with no cells, a non-positive or
// non-finite radius, or derived data (centres, planes) that does not match the cells.
void checkPattern(const FracturePattern& pattern, const std::string& what);

// 3D Voronoi cells (voro++) of `cells` seeded sites in the half ball z >= 0 of radius
// siteRadius; a site's distance from the origin is siteRadius·u^biasExponent (u uniform), so
// an exponent above 1/3 packs cells toward the impact (small near it, large far away).
// The diagram is bounded by a box of half-size 2·siteRadius.
struct VoronoiPatternSettings {
    int cells = 64;            // number of sites, >= 1
    double radius = 1.0;       // m (pattern units): cells with their site within it break free
    double siteRadius = 0.0;   // m; 0 picks 1.5 × radius
    double biasExponent = 1.0; // >= 0; 1/3 is uniform density
    void check(const std::string& what) const;
};
FracturePattern voronoiPattern(const VoronoiPatternSettings& settings, std::uint64_t seed);

// Radial sectors × rings in the xy plane (for thin sheets: the axis is the sheet normal),
// each cell a prism through z in [-outer, outer]. Ring k ends at firstRing·growth^k; every
// ring corner is jittered by up to `jitter` of its ring's width and every sector boundary by
// up to `jitter` of the sector angle, shared by the neighbouring cells so the cells fit.
struct GlassPatternSettings {
    int sectors = 12;          // >= 3
    int rings = 5;             // >= 1
    double firstRing = 0.05;   // m, radius of the innermost ring
    double growth = 1.6;       // > 1, ratio of successive ring radii
    double jitter = 0.3;       // in [0, 0.45]
    double radius = 0.0;       // m, cells within it break free; 0 picks the outermost ring
    void check(const std::string& what) const;
};
FracturePattern glassPattern(const GlassPatternSettings& settings, std::uint64_t seed);

// Voronoi cells of a regular grid of sites (count³ cubes of edge `cellSize`, centred on the
// origin in x and y and starting at z = -cellSize/2), each site moved by up to `jitter`
// cell sizes along each axis.
struct GridPatternSettings {
    int count = 4;            // cells per axis, >= 1
    double cellSize = 0.25;   // m
    double jitter = 0.25;     // in [0, 0.45]
    double radius = 0.0;      // m; 0 picks every cell
    void check(const std::string& what) const;
};
FracturePattern gridPattern(const GridPatternSettings& settings, std::uint64_t seed);

// One cell per OBJ object (`o`/`g`), each a closed convex polyhedron; radius = the largest
// centroid distance, so every cell breaks free (set pattern.radius to change it). Throws
// shatter::InputError naming the file and the object for an open, non-convex or flat cell.
FracturePattern loadPattern(const std::string& objPath);
// The same from a file already read (fuzzing, tests).
FracturePattern patternFromObj(const geometry::ObjFile& file);

} // namespace shatter::fracture
