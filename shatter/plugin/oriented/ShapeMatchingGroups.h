#pragma once
// Generalized shape matching (source 000 §3.2.1 eq. 1, §3.2.3): one group per particle,
// holding the particle and its neighbours in the connection graph.
#include <shatter/plugin/oriented/OrientedParticles.h>
#include <shatter/plugin/oriented/SimdLanes.h>

#include <algorithm>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

namespace shatter::oriented {

class ShapeMatchingGroups {
public:
    // Group g = particle g and every particle connected to it (pairs (a, b), any order).
    // Throws shatter::InputError for a pair naming a particle outside [0, particles.size()).
    ShapeMatchingGroups(const OrientedParticles& particles, const std::vector<std::pair<int, int>>& connections);
    // Becomes what the constructor makes of (particles, connections), bit for bit (a new
    // connectionsVersion, every rotation the identity), in the memory it already holds: a torn
    // body that keeps one part rebuilds its groups without fresh pages in the frame of the tear.
    void rebuild(const OrientedParticles& particles, const std::vector<std::pair<int, int>>& connections);

    int size() const { return int(offsets_.size()) - 1; }
    std::span<const int> members(int g) const {
        return {members_.data() + offsets_[g], size_t(offsets_[g + 1] - offsets_[g])};
    }
    // Recomputes the rest data (mass, rest centre, rest moment Ā) from the particles' rest
    // pose; call after the rest pose changed (plastic deformation).
    void updateRest(const OrientedParticles& particles);
    // Drops the connections `pairs` (a, b): b leaves a's group and a leaves b's, in place. The
    // groups are then those the constructor makes of the connections left (members and rest
    // data bit for bit): only the groups that lost a member get their rest data again; every
    // other group, and every group's rotation (the warm start of its next fit), is kept. Throws
    // shatter::InputError for a pair that is not a connection of the groups. The particles' rest
    // pose and masses must be those of the last updateRest (or the constructor): the kept
    // members' offsets come from the snapshot taken there, so a changed rest pose without
    // updateRest would leave a changed group whose Σ m r̄ is not 0. (ShapeMatchingGroupsRemoval.cpp)
    void removeConnections(const OrientedParticles& particles, std::span<const std::pair<int, int>> pairs);

    // Moment matrix of group g at positions x and orientations q (eq. 1):
    // A = Σ_j (R_j C_j + m_j (x_j − x_cm)(x̄_j − x̄_cm)ᵀ), the same as the source's form
    // Σ (A_j + m_j x_j x̄_jᵀ) − M x_cm x̄_cmᵀ without its cancellation far from the origin.
    Eigen::Matrix3d moment(int g, const OrientedParticles& particles, std::span<const Eigen::Vector3d> x,
                           std::span<const Eigen::Quaterniond> q) const;
    // Deformation matrix D = A Ā⁻¹ of group g (source 000 §3.3): the best-fit affine map from
    // the rest pose; R at a rigid rotation R, the identity at rest.
    Eigen::Matrix3d deformation(int g, const OrientedParticles& particles, std::span<const Eigen::Vector3d> x,
                                std::span<const Eigen::Quaterniond> q) const;

    // deformation(g, …) of every group at once: each particle's moment R_j C_j is computed
    // once, not once per group that holds it (the visual mesh asks for all of them). On
    // `path`'s instruction set, the same bits on every path (shatter::InputError for a path
    // this processor lacks): the portable sums took 68 instructions a member, the AVX2 ones 28.
    std::vector<Eigen::Matrix3d> deformations(const OrientedParticles& particles, std::span<const Eigen::Vector3d> x,
                                              std::span<const Eigen::Quaterniond> q,
                                              SimdPath path = fastestSimdPath()) const;

    // The rotation of group g's best fit at (x, q), warm-started from the last fit; also
    // stored as the next warm start.
    Eigen::Quaterniond fitRotation(int g, const OrientedParticles& particles, std::span<const Eigen::Vector3d> x,
                                   std::span<const Eigen::Quaterniond> q, int rotationIterations);

    // Whether particles a and b are connected (b is in a's group). Inline: a self-contact
    // list's walk asks it of every pair of touching neighbours (22,600 a walk in a
    // 4,900-primitive sheet), where the call cost as much as the search. A scan of the sorted
    // neighbours up to b, not a binary search: a group is a particle's neighbours (9 in the
    // sheet), and the scan took half the binary search's instructions and branches.
    bool connected(int a, int b) const {
        const auto group = members(a);
        for (auto m = group.begin() + 1; m != group.end(); ++m)
            if (*m >= b) return *m == b;
        return false;
    }
    // Changes whenever what is connected changes, so a cache of connected() keyed by it is
    // current while it is the same: a number no other groups built in this process have (a
    // copy has its original's), with the member count, which only removeConnections changes
    // (it lowers it).
    std::pair<std::uint64_t, size_t> connectionsVersion() const { return {id_, members_.size()}; }

    // Caches every particle's moment R_j C_j at orientations q, and which particles are
    // fixed, for project(), which keeps the moments current for the orientations it changes
    // itself; call again after anything else changed q (prediction, bend constraints) or the
    // fixed flags. On `path` (the same bits, particles.moment's, on every path; 4 particles at
    // once on AVX2; shatter::InputError for a path this processor lacks).
    void refreshMoments(const OrientedParticles& particles, std::span<const Eigen::Quaterniond> q,
                        SimdPath path = fastestSimdPath());
    // The moments R_j C_j that refreshMoments cached and project() keeps current, per particle.
    std::span<const Eigen::Matrix3d> cachedMoments() const { return rotatedMoment_; }

    // One projection of group g: its rotation R (extracted from A, warm-started from the
    // last call), goals g_j = R (x̄_j − x̄_cm) + x_cm, every free member moved by
    // stiffness × (g_j − x_j), and the centre particle's orientation turned towards R by the
    // same fraction (only the centre takes the group's rotation). Σ m Δx = 0 when no member
    // is fixed. `rotationIterations` bounds the warm-started rotation extraction, which also
    // ends after a Newton step under `newtonStop` (rad; extractRotation). Reads the members'
    // moments from refreshMoments.
    void project(int g, const OrientedParticles& particles, std::span<Eigen::Vector3d> x,
                 std::span<Eigen::Quaterniond> q, double stiffness, int rotationIterations,
                 double newtonStop = 1e-8);
    // One sweep: project(g, …) of every group, batch by batch (batch(b)). The groups of a
    // batch share no particle, so their projections are independent: the same as one after
    // the other in the batch's order, but their rotation fits run as interleaved lanes
    // (extractRotations), whose dependent chains then overlap. The sweep runs on `path`'s
    // instruction set (the same bits on every path; shatter::InputError for a path this
    // processor lacks).
    void projectAll(const OrientedParticles& particles, std::span<Eigen::Vector3d> x,
                    std::span<Eigen::Quaterniond> q, double stiffness, int rotationIterations,
                    double newtonStop = 1e-8, SimdPath path = fastestSimdPath());
    // projectAll for one of a run of sweeps over the same x (a solver step's iterations) that
    // change x between them only at the particles `touched` (its contacts'): the same bits as
    // projectAll. On AVX2 the sweep's padded copy of x is kept from the run's last sweep (all
    // of x is copied in for the `first` sweep of a run, only x[touched] for the others) and only
    // x[touched] is copied out, all of x after the `last` (a copy in and out of all 4,900
    // particles each sweep was 1.3% of the sheet bench's instructions). Between the sweeps of a
    // run, x is current only at `touched`. Duplicates in `touched` are harmless; an index
    // outside x is shatter::InputError (checked at the first sweep), a later sweep over x of
    // another size std::logic_error.
    // With `omega` > 0 the run's sweeps are accelerated (SolverSettings::chebyshevRadius): this
    // sweep's motion δ (x after its projections − x before, per particle) becomes
    // Δ = omega δ + (omega − 1) Δ_last, Δ_last the run's last sweep's Δ, and x = x before + Δ
    // (the `first` sweep only keeps Δ = δ; its omega, 1 in Chebyshev's schedule, is not used).
    // Σ m Δ = 0 while Σ m δ = 0 (no fixed member moves). The same bits on every path; omega 0:
    // the plain sweeps, bit for bit (a run of one sweep is always plain).
    void projectAllInRun(const OrientedParticles& particles, std::span<Eigen::Vector3d> x,
                         std::span<Eigen::Quaterniond> q, double stiffness, int rotationIterations,
                         double newtonStop, SimdPath path, bool first, bool last, std::span<const int> touched,
                         double omega = 0.0);
    // The sweep's order: batches of up to kRotationLanes groups that share no particle, every
    // group in one. Greedy near the order of the groups: a batch starts at the first group not
    // yet placed and takes the next ones within a window of it that share no particle with
    // those it holds (in a grid, groups a few rows apart: {g, g+3, g+6, g+9}, then
    // {g+1, g+4, …}), so a sweep walks the particles near-sequentially. Made with the groups;
    // removeConnections keeps it (losing members adds no sharing).
    int batches() const { return int(batchStart_.size()) - 1; }
    std::span<const int> batch(int b) const {
        return {order_.data() + batchStart_[b], size_t(batchStart_[b + 1] - batchStart_[b])};
    }

    Eigen::Quaterniond rotation(int g) const { return rotation_[g]; }
    // The warm start of group g's next fit (e.g. advanced by the centre's predicted spin).
    void setRotation(int g, const Eigen::Quaterniond& q) { rotation_[g] = q; }

private:
    // The constructor's work (all but the id), into the vectors as they are.
    void build(const OrientedParticles& particles, const std::vector<std::pair<int, int>>& connections);
    // The sweep's batches (batch()) of the groups as they are.
    void orderBatches();
    // project() of the groups of one batch (at most kRotationLanes, sharing no particle), the
    // fits on `path`; defined (always inlined) in ShapeMatchingGroups.cpp only.
    // x: Eigen's 3-vectors on the portable path, the sweep's padded copy (sweepPositions_) on AVX2.
    inline void projectBatch(std::span<const int> groups, const OrientedParticles& particles, double* x,
                             std::span<Eigen::Quaterniond> q, double stiffness, int rotationIterations,
                             double newtonStop, SimdPath path);
    // x into sweepPositions_ and back, around an AVX2 sweep.
    void padPositions(std::span<const Eigen::Vector3d> x);
    void unpadPositions(std::span<Eigen::Vector3d> x) const;
    // An accelerated sweep on the portable path (projectAllInRun's omega): x into sweepStart_
    // before it, and its motion since extrapolated after it.
    void keepSweepStart(std::span<const Eigen::Vector3d> x);
    void accelerateSweep(std::span<Eigen::Vector3d> x, double omega, bool first);
    // accelerateSweep on sweepPositions_ (AVX2), from sweepStart_, which it then sets to the
    // result (the next sweep's start but for the touched particles).
    void accelerateSweepAvx2(double omega, bool first);
    // projectAll's sweep compiled for each path.
    void projectAllPortable(const OrientedParticles& particles, std::span<Eigen::Vector3d> x,
                            std::span<Eigen::Quaterniond> q, double stiffness, int rotationIterations,
                            double newtonStop);
    void projectAllAvx2(const OrientedParticles& particles, std::span<Eigen::Quaterniond> q, double stiffness,
                        int rotationIterations, double newtonStop);
    // deformations() into D (one matrix a group), compiled for each path: `wide` as sums'.
    template <bool wide>
    void deformationsOn(const OrientedParticles& particles, std::span<const Eigen::Vector3d> x,
                        std::span<const Eigen::Quaterniond> q, std::span<Eigen::Matrix3d> D) const;
    // refreshMoments's moments on AVX2.
    void refreshMomentsAvx2(const OrientedParticles& particles, std::span<const Eigen::Quaterniond> q);
    void deformationsAvx2(const OrientedParticles& particles, std::span<const Eigen::Vector3d> x,
                          std::span<const Eigen::Quaterniond> q, std::span<Eigen::Matrix3d> D) const;
    // Group g's rest data (mass, rest centre, Ā⁻¹) from the particles' rest pose.
    void updateRest(int g, const OrientedParticles& particles);
    // Group g's moment A = Σ_j (R_j C_j + m_j (x_j − x_cm) r̄_jᵀ) and centre x_cm at positions
    // x, R_j C_j = moment(j) (a matrix, or a reference to one), summed over its members in one
    // pass: what project(), moment() and deformations() share. `wide`: compiled for 4-wide
    // lanes (AVX2), where a broadcast is one instruction (the same bits either way).
    struct Sums {
        Eigen::Matrix3d A;
        Eigen::Vector3d centre;
    };
    // x_j is x + stride × j: stride 3 for Eigen's 3-vectors, 4 for the padded sweep copy.
    template <bool wide, int stride, typename Moment>
    Sums sums(int g, const double* x, const Moment& moment) const;

    // A point padded to 32 bytes: the projection's loops load and store it as one 4-lane row.
    // From Eigen's 24-byte vectors, a load took 3 instructions and a store 3, and the sums'
    // three broadcasts 6 (a copy in and out per sweep costs far less: each particle is read and
    // written by the ~9 groups that hold it).
    struct PaddedPoint {
        alignas(32) double v[4] = {0.0, 0.0, 0.0, 0.0};
    };
    // The sweep reads sweepPositions_ and restPoint_ as flat arrays (particle j's at 4 j).
    static_assert(sizeof(PaddedPoint) == 4 * sizeof(double));

    std::uint64_t id_;
    std::vector<int> offsets_; // group g's members are members_[offsets_[g] .. offsets_[g+1])
    std::vector<int> members_; // the centre particle first, then the others ascending
    // Per particle, as updateRest read them: the rest position padded with 1, (x̄_j, 1), and the
    // mass m_j. A member's rest offset r̄_j = x̄_j − x̄_cm and its (m_j r̄_j, m_j) are made from
    // them in the sweep's loops (the bits updateRest's subtraction and product make), not read
    // from per-member storage: 64 bytes a member (43,000 in a 4,900-particle sheet, 2.75 MB a
    // sweep) streamed from beyond L2 every sweep, where its load was a third of the sweep's
    // time; the particles' 200 kB are read near-sequentially and stay in cache.
    std::vector<PaddedPoint> restPoint_;
    std::vector<double> mass_;
    std::vector<Eigen::Matrix3d> rotatedMoment_; // per particle, R_j C_j (refreshMoments)
    std::vector<unsigned char> fixed_;           // per particle, particles.fixed (refreshMoments)
    bool anyFixed_ = false;                      // whether any of fixed_ is set
    std::vector<double> totalMass_;
    std::vector<Eigen::Vector3d> restCentre_;
    std::vector<Eigen::Matrix3d> restMomentInverse_;
    std::vector<Eigen::Quaterniond> rotation_;
    std::vector<int> order_;      // the groups, batch after batch
    std::vector<int> batchStart_; // batch b is order_[batchStart_[b] .. batchStart_[b+1])
    std::vector<PaddedPoint> sweepPositions_;    // per particle, x padded (projectAll on AVX2)
    // Per particle, an accelerated run's x before the sweep and the last sweep's motion Δ.
    std::vector<PaddedPoint> sweepStart_, sweepDelta_;
};

} // namespace shatter::oriented
