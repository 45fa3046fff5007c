#pragma once
// Cleaving planes (source 002 §2, Fig. 1 and 3): the links whose shared face lies on or near a
// plane get their strength multiplied, so the body tends to split along it (a scored glass
// top, a mortar joint) or, with a factor above 1, to hold together there.
#include <shatter/plugin/lattice/Lattice.h>

#include <Eigen/Core>
#include <string>
#include <vector>

namespace shatter::lattice {

struct CleavingPlane {
    Eigen::Vector3d point = Eigen::Vector3d::Zero();    // a point on the plane, mesh coordinates (m)
    Eigen::Vector3d normal = Eigen::Vector3d::UnitX();  // any length but zero
    // A link is affected when the plane cuts through its shared face or the face's centre is
    // within this distance of the plane (m); 0 = faces cut by or lying in the plane.
    double distance = 0.0;
    double factor = 0.25; // strength multiplier, > 0 (< 1 weakens)
    // A crack that reaches the plane runs along it, as a scored glass sheet parts along its
    // score: when a link of the plane between tets on its two sides breaks, every such link
    // joined to it through their faces (sharing edges) breaks in the same step (runCracks),
    // parting the body into the tets on either side. Weakening alone
    // cannot part a body along a plane: this lattice (one link per shared face, about 1.6 per
    // tet where a rigid frame needs 3) holds a load by the inertia of the tets around it, so
    // the forces fall off by about 3 per link away from it and never reach the rest of the
    // plane (the table top of 002 Fig. 3 made a hole even with its plane at 0.3% strength).
    bool crackRuns = false;

    // A finite point, a finite non-zero normal, a distance >= 0, a factor > 0; `index` names
    // the plane in the message.
    void check(const std::string& body, int index) const;
};

// Multiplies the base and current strength of every affected link by the plane's factor
// (planes compound) and, when the plane's cracks run, marks it if it joins tets on the plane's
// two sides. Returns the number of links each plane affected.
std::vector<int> applyCleavingPlanes(Lattice& lattice, const std::vector<CleavingPlane>& planes);

// Breaks the links a crack runs along from the links broken[from...] (Link::crackRuns): every
// unbroken link on a running plane joined to one of them that lies on one too through such
// links whose faces share an edge; appends them to `broken`. Links of infinite strength (bound
// slivers) stay and stop the run.
void runCracks(Lattice& lattice, std::vector<int>& broken, size_t from);

// Whether the plane affects the link (see CleavingPlane::distance).
bool faceNearPlane(const Lattice& lattice, const Link& link, const CleavingPlane& plane);

} // namespace shatter::lattice
