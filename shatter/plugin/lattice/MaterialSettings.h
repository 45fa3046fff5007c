#pragma once
// What a breakable body is made of: density and the strength of its links per unit area.
#include <string>
#include <vector>

namespace shatter::lattice {

// A link's strength is its shared face area times `strength` (source 002 §2: "strength
// proportional to the area of the shared face"), so Pa × m² gives newtons.
//
// The lattice's link forces are not continuum stresses: they are the forces that keep a
// mechanism of point masses rigid under the impulse of one Bullet step, spread over a few
// particles (002 §3.2), and they fall off by about 3 per link away from the load. A particle's
// share of an impact does not depend on the mesh while a link's strength goes with its face
// area, so the same material looks weaker on a finer mesh (about 1/h² for tets of size h) and
// at a shorter step. Real tensile strengths (adobe 0.1-0.3 MPa, fired brick 1-3 MPa, concrete
// 2-5 MPa, float glass 30-60 MPa, porcelain 30-60 MPa) therefore make no sense here as such;
// the presets are effective strengths, calibrated on the demos at 1/240 s: adobe and brick on
// the wall's 10 cm tets (a 400 kg ball at 9 m/s holes adobe, barely marks brick), glass and
// ceramic on the table's 4 × 4 × 2 cm tets (an 8 kg ball at 6 m/s goes through the glass top).
// Densities are the real ones. For a mesh of tets of size h, multiply by (h_demo / h)².
struct MaterialSettings {
    std::string name = "adobe";
    double density = 1700.0;        // kg/m³
    double strength = 2.0e5;        // Pa: tensile link strength per m² of shared face
    double compressionRatio = 4.0;  // compressive strength / tensile strength (brittle: > 1)

    // Density, strength and compression ratio must be positive and finite.
    void check(const std::string& body) const;
};

MaterialSettings adobe();    // 1700 kg/m³, 0.2 MPa, compression ×4
MaterialSettings brick();    // 1900 kg/m³, 1.5 MPa, compression ×8
MaterialSettings concrete(); // 2400 kg/m³, 3 MPa, compression ×10
MaterialSettings glass();    // 2500 kg/m³, 0.25 MPa, compression ×10
MaterialSettings ceramic();  // 2400 kg/m³, 0.3 MPa, compression ×10

// The presets by name ("adobe", "brick", "concrete", "glass", "ceramic"); throws
// shatter::InputError listing the names for any other.
MaterialSettings materialNamed(const std::string& name);
std::vector<std::string> materialNames();


} // namespace shatter::lattice
