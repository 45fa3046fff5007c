#pragma once
// The breakable lattice (source 002 §2): one particle per tet at its centroid with the tet's
// mass, one distance constraint ("link") per pair of tets that share a face, whose strength is
// the face area times the material strength.
#include <shatter/plugin/lattice/MaterialSettings.h>
#include <shatter/plugin/lattice/TetFaces.h>
#include <shatter/plugin/lattice/TetMesh.h>

#include <Eigen/Core>

#include <span>
#include <vector>

namespace shatter::lattice {

struct Particle {
    Eigen::Vector3d position; // tet centroid, mesh coordinates (m)
    double volume = 0.0;      // m³
    double mass = 0.0;        // kg
    bool fixed = false;       // infinite mass (anchored, e.g. to the ground)
};

struct Link {
    int a = -1, b = -1;               // particles (tets), a < b
    Eigen::Vector3d normal;           // (p_a - p_b) / |p_a - p_b|: the gradient of C = |p_a - p_b| - d wrt p_a
    double length = 0.0;              // rest distance d (m)
    double area = 0.0;                // shared face area (m²)
    Eigen::Vector3d faceCentre;       // centroid of the shared face (m)
    std::array<int, 3> face{};        // the shared face's nodes
    double baseStrength = 0.0;        // N: area × material strength × cleaving/noise factors
    double strength = 0.0;            // N: now (weakened by loads and by damage spreading)
    bool crackRuns = false;           // on a cleaving plane that a crack runs along (CleavingPlane::crackRuns)
    bool broken = false;
};

class Lattice {
public:
    // Validates the mesh (validateTetMesh) and the material (MaterialSettings::check); throws
    // shatter::InputError naming the mesh.
    Lattice(TetMesh mesh, const MaterialSettings& material);

    const TetMesh& mesh() const { return mesh_; }
    const MaterialSettings& material() const { return material_; }
    const TetFaces& faces() const { return faces_; }
    const std::vector<Particle>& particles() const { return particles_; }
    const std::vector<Link>& links() const { return links_; }
    int particleCount() const { return int(particles_.size()); }
    int linkCount() const { return int(links_.size()); }
    int brokenCount() const { return brokenCount_; }
    // Link::broken, kept apart one byte per link: a pass over 100,000 rows that only asks this
    // (ConstraintSystem::restrictTo) reads 100 KB instead of a 150-byte Link per row.
    bool isBroken(int link) const { return broken_[size_t(link)] != 0; }
    // Broken links joined again so far (joinLink): a constraint system built before a join
    // lacks their rows.
    int joinedCount() const { return int(joined_.size()); }
    // The broken links joined again after the first `count` (in the order they were joined).
    std::span<const int> joinedSince(int count) const { return std::span<const int>(joined_).subspan(size_t(count)); }
    double totalMass() const { return totalMass_; }

    // Links of a particle, broken ones included (check Link::broken).
    std::span<const int> linksOf(int particle) const {
        return {linkIndex_.data() + linkStart_[particle], linkIndex_.data() + linkStart_[particle + 1]};
    }
    int otherEnd(int link, int particle) const { return links_[link].a == particle ? links_[link].b : links_[link].a; }
    double inverseMass(int particle) const { return particles_[particle].fixed ? 0.0 : 1.0 / particles_[particle].mass; }

    void setFixed(int particle, bool fixed) { particles_[particle].fixed = fixed; }
    // Multiplies both the base and the current strength (cleaving planes, noise).
    void scaleStrength(int link, double factor);
    void setCrackRuns(int link) { links_[link].crackRuns = true; }
    // Lowers the current strength by `amount` N (never raises it).
    void weaken(int link, double amount);
    void breakLink(int link);
    // Joins the link for good: unbroken again, with infinite strength, so nothing weakens or
    // breaks it (pieces below the minimum fragment size: FragmentClusters.h).
    void joinLink(int link);

private:
    TetMesh mesh_;
    MaterialSettings material_;
    TetFaces faces_;
    std::vector<Particle> particles_;
    std::vector<Link> links_;
    std::vector<int> linkStart_, linkIndex_;
    std::vector<char> broken_; // Link::broken of each link (isBroken)
    int brokenCount_ = 0;
    std::vector<int> joined_; // broken links joined again, in order (joinLink)
    double totalMass_ = 0.0;
};

// Tets that have a face with all three nodes within `tolerance` (m) of the plane n·x = offset
// (mesh coordinates), e.g. the bottom layer of a wall standing on the ground.
std::vector<int> tetsWithFaceOnPlane(const TetMesh& mesh, const Eigen::Vector3d& normal, double offset, double tolerance);

} // namespace shatter::lattice
