#pragma once
// A crack at run time: a polyline of massless crack particles advected with the material,
// the tracked displacements of its two surfaces, and the state of its two tips.
#include <shatter/plugin/mpm/Types.h>

#include <array>
#include <deque>
#include <limits>
#include <vector>

namespace shatter::mpm {

// What the crack-tip analysis found at one tip (all zero until it has run once).
struct TipResult {
    int crack = 0;
    int tip = 0;                     // 0: the polyline's first point ("start"), 1: its last ("end")
    Vec2 position = Vec2::Zero();
    double J = 0;                    // energy release rate, J/m² (N/m)
    double KI = 0, KII = 0;          // stress intensity factors, Pa·√m
    double theta = 0;                // predicted kink angle, rad, relative to the tip direction
    int grew = 0;                    // growth steps since the last frame
    bool valid = false;              // false when the contour could not be built
    std::vector<Vec2> contour;       // the J-integral contour points (for pictures)
};

struct CrackTip {
    bool active = false;      // this end is a crack tip (the scene's `tips`)
    bool propagates = false;  // it may grow
    bool exited = false;      // it reached the body's outline: the crack is through
    double lastGrowthTime = -std::numeric_limits<double>::infinity();
    // Low-pass filtered K_I, K_II (see CrackGrowthSettings::filterTransits).
    double filteredKI = 0, filteredKII = 0;
    bool filterPrimed = false;
    std::deque<Vec2> guide;   // remaining guide points, nearest first
    TipResult result;
};

struct Crack {
    std::vector<Vec2> points;   // crack particles, first to last
    // Where the two crack surfaces are, as offsets from each crack particle: the surface on
    // the left ("above") is at points[k] + above[k]. above − below is the crack opening.
    std::vector<Vec2> above;
    std::vector<Vec2> below;
    std::array<CrackTip, 2> tips;

    // The tip point and the unit direction it grows in (from its neighbour to it).
    Vec2 tipPosition(int tip) const { return tip == 0 ? points.front() : points.back(); }
    Vec2 tipDirection(int tip) const;
    // Appends a new tip point (its surfaces start closed: new crack faces have not opened).
    void extend(int tip, const Vec2& p);
};

} // namespace shatter::mpm
