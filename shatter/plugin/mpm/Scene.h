#pragma once
// Everything a 2D crack simulation needs, as plain data: what loadScene() reads from a
// scene file and what Solver2D is built from. Units are SI; bodies have unit thickness
// (1 m), so forces are N per metre of thickness and a 2D "volume" is an area in m².
#include <shatter/plugin/mpm/BSpline.h>
#include <shatter/plugin/mpm/Collider.h>
#include <shatter/plugin/mpm/Material.h>
#include <shatter/plugin/mpm/Shape.h>
#include <shatter/plugin/mpm/Types.h>

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace shatter::mpm {

enum class VelocityTransfer {
    Apic, // affine particle-in-cell (Jiang et al. 2015): conserves angular momentum
    Pic,  // the source's plain PIC (eq. 18): dissipative
};

struct GridSettings {
    double dx = 0;          // cell size, m (required)
    int ppc = 2;            // particles per cell per axis (so ppc² per cell); spacing dx/ppc
    KernelType kernel = KernelType::Cubic;
    double jitter = 0;      // random particle offset, as a fraction of the spacing (uses the seed)
};

struct TimeSettings {
    double end = 1;         // s
    double frame = 1.0 / 24; // s between outputs
    double cfl = 0.4;       // Δt = cfl·dx / (wave speed + largest particle speed)
    double maxStep = std::numeric_limits<double>::infinity(); // s, optional upper bound on Δt
};

struct Body {
    Shape shape;
    int material = 0;       // index into Scene::materials
    Vec2 velocity = Vec2::Zero();
};

enum class TipSelection { Both, Start, End, None };

struct CrackSpec {
    std::vector<Vec2> points;  // polyline; "above" is the left side walking from first to last
    bool propagate = false;
    TipSelection tips = TipSelection::Both; // which ends are crack tips
    std::vector<Vec2> guide;   // optional path the nearest tip follows when it grows
};

struct Load {
    // Traction: the vector `value` (Pa) on the outline inside the region. Pressure: `pressure`
    // (Pa) along the outline's inward normal (positive pushes, negative pulls). Force: the
    // total `value` (N) shared by the particles inside the region.
    enum class Kind { Traction, Force, Pressure };
    Box region;
    Kind kind = Kind::Traction;
    Vec2 value = Vec2::Zero(); // traction in Pa, or total force in N
    double ramp = 0;           // s of linear rise from zero (0: applied at once)
    double pressure = 0;       // Pa, Kind::Pressure
    // Traction and pressure: when not zero, only the outline whose outward normal is within
    // 45° of this direction is loaded (e.g. [0, 1]: the top edge, not the sides the region
    // also reaches).
    Vec2 facing = Vec2::Zero();
};

// Settings of the crack-tip machinery (J-integral, growth), all with the source's defaults.
struct CrackGrowthSettings {
    double contourRadiusCells = 2;   // J contour radius in cells (Guo & Nairn 2006)
    int contourSegments = 16;
    double growthCells = 0.5;        // length added per growth step, in cells
    // Mode-mixity dead band: |K_II/K_I| below this is indistinguishable from zero at the
    // solver's measured accuracy (|K_II| < 2% K_I in symmetric validation) and grows straight.
    double mixityTolerance = 0.02;
    // Tip speed limit as a fraction of the Rayleigh wave speed, the bound of dynamic fracture
    // mechanics; a tip grows at most one step per growthLength/(this·c_R).
    double speedLimit = 1.0;
    // Time constant of the low-pass filter on K_I, K_II, in units of the shear-wave transit
    // time of the contour diameter; 0 disables the filter.
    double filterTransits = 1.0;
    // Propagating tips are analysed (J-integral, K, growth decision) once per this many cells
    // crossed by the fastest wave: every N substeps, N = this·dx / (fastest signal·Δt), at
    // least 1. The near-tip field cannot change faster; under the CFL step (cfl < this) it
    // is every substep. 0: every substep, always.
    double analysisCells = 0.5;
};

struct Scene {
    std::string source;     // file it came from, for messages
    Analysis analysis = Analysis::PlaneStress;
    Vec2 gravity = Vec2::Zero();
    GridSettings grid;
    TimeSettings time;
    VelocityTransfer transfer = VelocityTransfer::Apic;
    std::vector<Material> materials;
    std::vector<Body> bodies;
    std::vector<CrackSpec> cracks;
    std::vector<Load> loads;
    std::vector<Box> fixed;
    ColliderList colliders;
    double damping = 0;     // 1/s, viscous damping of grid velocities
    CrackGrowthSettings fracture;
    std::uint64_t seed = 1;
};

} // namespace shatter::mpm
