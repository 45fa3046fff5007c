#pragma once
// Constraint forces of the lattice (source 002 §3.2, eqs. 5-14): the Lagrange multipliers λ
// of J M⁻¹ Jᵀ λ = -J̇ q̇ - J M⁻¹ Q, by matrix-free conjugate gradients.
//
// Sign: the force of link k on its particle a is normal_k λ_k and on b is -normal_k λ_k
// (normal = (p_a - p_b)/|p_a - p_b|), so λ > 0 pushes the ends apart (compression) and
// λ < 0 pulls them together (tension).
//
// Redundant links (more links on a cluster of particles than it has degrees of freedom, e.g.
// a tet whose four neighbours are all fixed) make J M⁻¹ Jᵀ singular. The source asks for the
// minimum-norm λ there. Plain CG started in the range of the matrix stays in it and converges
// to exactly that solution; a warm start from the previous step's λ keeps the property, since
// that λ is in the range of the old matrix and removing links (rows) or splitting the body
// (blocks) maps the range into the new one. The Jacobi preconditioner keeps that where the
// redundancy is local (the rows of a tet whose neighbours are all fixed share one diagonal
// value). A block-Jacobi one (the rows of each free particle together) saved only 17% of the
// iterations on a 55,411-tet body, less than it costs to build and apply. An additive two-level
// one (6 stress modes n nᵀ per cluster of 8 particles, coarse matrix by Eigen's LDLT) saved 27% of
// the iterations of the solves over every row on wall seed 6, but its setup per system was ~430 M
// instructions, and on a large body most iterations are in the local regions (notes/latticepre.md).
#include <shatter/plugin/lattice/ConjugateGradientStep.h>
#include <shatter/plugin/lattice/Lattice.h>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <cmath>
#include <functional>
#include <string>
#include <vector>

namespace shatter::lattice {

struct ConstraintSolverSettings {
    // Stop when ‖b - Aλ‖ ≤ tolerance · ‖b‖. 1e-6 leaves each link force off by about a
    // millionth of the load scale, far below any strength difference that decides a break.
    // 1e-4 broke the same links on the lattice benchmark's coarse meshes (wall seeds 1-8,
    // table, noise; CG 40% fewer instructions) but not on a fine real mesh: the 10,274-tet
    // Spot hit at 30 m/s shed 16 pieces instead of 38 (RealShape.FineSpotStatue...), so the
    // error that decides breaks grows with the mesh's resolution.
    double tolerance = 1e-6;
    int maxIterations = 2000;
    // Called after every iteration with the iteration number, λ and the relative residual
    // (tests use it to watch the convergence).
    std::function<void(int, const Eigen::VectorXd&, double)> onIteration;

    void check(const std::string& body) const;
};

struct SolveResult {
    int iterations = 0;
    double residual = 0.0; // relative: ‖b - Aλ‖ / ‖b‖ (0 when b = 0)
    bool converged = false;
    int rowsSolved = 0;    // rows of the largest region CG ran on (all of them for a cold start)
    bool provenSafe = false; // stopped before the tolerance: the exact λ is proven inside the SafeRange
    // Stopped before the tolerance: every row's exact λ is proven on the same side of the
    // SafeRange's break range as its current one, and some row is beyond it.
    bool breaksDecided = false;
};

// Where a solve may stop before its tolerance: a range of λ per row, and a proven lower bound μ
// on the smallest eigenvalue of the Jacobi-scaled matrix (scaledEigenvalueLowerBound). For any
// λ with residual r = b - Aλ, the exact solution λ* = λ + A⁻¹r satisfies
//     |λ*_k - λ_k| = |e_kᵀ D^-½ Â⁻¹ D^-½ r| ≤ ‖D^-½ r‖ / (μ √d_k)     (D = diag A, Â = D^-½ A D^-½)
// since ‖Â⁻¹‖ = 1/λ_min(Â) ≤ 1/μ. When that interval lies strictly inside (lower_k, upper_k) on
// every row, the exact forces are inside the range, and so are the current ones.
//
// The same interval decides which links break: when, on every row, it lies entirely inside or
// entirely outside (breakLower_k, breakUpper_k), the range beyond which a link breaks, and some
// row is outside, the exact forces break exactly the links the current ones break. A solve that
// only has to tell which links break (they break, the system loses their rows and is solved
// again) may stop there.
struct SafeRange {
    double eigenvalueBound = 0.0;        // μ > 0
    std::vector<double> lower, upper;    // per row
    std::vector<double> breakLower, breakUpper; // per row; empty: the solve does not stop for it
};

// The linear system of one connected piece of a lattice: its particles (lattice indices) and
// the unbroken links between them that involve at least one free particle (a link between
// two fixed particles carries no computable force). Local numbering follows the given order.
class ConstraintSystem {
public:
    // `particles` ascending (as LatticePiece keeps them).
    ConstraintSystem(const Lattice& lattice, std::vector<int> particles, std::vector<int> links);

    int particleCount() const { return int(particles_.size()); }
    int rowCount() const { return int(links_.size()); }
    const std::vector<int>& particles() const { return particles_; } // local -> lattice particle
    const std::vector<int>& links() const { return links_; }         // local row -> lattice link

    // y = J M⁻¹ Jᵀ x, O(links).
    void multiply(const Eigen::VectorXd& x, Eigen::VectorXd& y) const;
    // J v for particle velocities v (3 per local particle); zero for any rigid motion.
    Eigen::VectorXd jacobianTimes(const Eigen::VectorXd& velocities) const;
    // Jᵀ λ: the constraint force on every local particle (3 per particle).
    Eigen::VectorXd constraintForces(const Eigen::VectorXd& lambda) const;
    // b = -J̇ q̇ - J M⁻¹ Q for external forces Q (3 per local particle, N) on a body moving
    // rigidly with angular velocity ω (rad/s, same axes as the lattice): -J̇ q̇ is the
    // centripetal term -|ω × d|²/|d| of each link.
    Eigen::VectorXd rightHandSide(const Eigen::VectorXd& forces, const Eigen::Vector3d& omega) const;
    // The same b, kept by the system from one call to the next: when ω has the same bits as
    // last time, only the rows at particles whose forces changed (bit for bit) are formed
    // again, each as rightHandSide forms it. A resting piece's analyses change the loads of a
    // few contact particles out of 50,000. Valid until the next call or restrictTo. Not
    // thread-safe, as solve.
    const Eigen::VectorXd& keptRightHandSide(const Eigen::VectorXd& forces, const Eigen::Vector3d& omega) const;

    // Conjugate gradients from the given λ (warm start; resized and zeroed if its size is
    // wrong). b = 0 gives λ = 0.
    //
    // Only where the residual is: a warm start leaves b - Aλ non-zero only near what changed
    // (new impacts, broken links), and a link's force falls off by about 3 per link away from
    // a load, so the correction is solved on the rows around those (every row of the free
    // particles within a few links of them; A restricted to them is a principal block, so CG
    // applies), the full residual is measured again, and the region grows until the whole
    // residual meets the tolerance. The stopping rule is the same as a solve over every row;
    // when the region would hold half the rows, every row is solved. A cold start has its
    // residual everywhere, so it is the plain solve.
    //
    // With a `safe` range, the solve stops as soon as the exact λ is proven inside it (at once,
    // when the warm start already proves it): each region's CG also stops when its scaled
    // residual falls to half of what would prove it at the start, the whole residual is
    // measured, and the proof is checked; if it fails there, the solve goes on to the tolerance.
    // With a break range in `safe`, it also stops as soon as the links that break are decided
    // (SafeRange): each region's CG checks its rows every few iterations, and when they look
    // decided the whole residual confirms it: the rows outside the region and its boundary keep
    // their λ and residual, so their part of the proof (scaled residual, distance to the break
    // range) is summed once per region (one pass over the other rows), and then only the
    // region's and its boundary's residuals are formed again (one product with the change of λ).
    // If the confirmation fails, CG goes on and checks with a 4 times larger margin, at most 3
    // confirmations per region before it goes on to the region's tolerance.
    // Not thread-safe: a solve keeps its product and marks in the system for the next one, so
    // one system is solved by one thread at a time.
    SolveResult solve(const Eigen::VectorXd& rhs, Eigen::VectorXd& lambda, const ConstraintSolverSettings& settings,
                      const SafeRange* safe = nullptr) const;

    // Whether restrictTo(lattice, particles) can make this system the one a constructor would
    // build over `particles` (from its links ascending, as LatticePiece lists them): they are
    // some of its particles, and if a broken link was joined since the system was built, its
    // rows are in ascending link order (where the joined links' rows go in).
    bool canRestrictTo(const Lattice& lattice, const std::vector<int>& particles) const;
    // Becomes the system over `particles` (ascending; canRestrictTo): drops the rows of links
    // broken since the system was built and of links leaving the particles, and their λ
    // (`lambda` holds one value per row), keeping the order of the rest; the links joined
    // since (Lattice::joinedSince) between two of the particles get their rows, in link order,
    // with λ = 0. O(rows + particles), no search: for the re-solves after breaks, and for the
    // rest of a piece that a part broke off (100,000 rows on a 55,000-tet body, built anew in
    // 43 M instructions; fragments below the minimum size join links before it).
    void restrictTo(const Lattice& lattice, const std::vector<int>& particles, Eigen::VectorXd& lambda);

    // The same matrix assembled (for a direct solver to compare with, and for tests).
    Eigen::SparseMatrix<double> assemble() const;

private:
    // Rows solved together, and the particles at their ends (local indices). `boundary`: the
    // other rows at a free one of those particles, whose residual changes with the region's λ
    // (every other row's residual is unchanged by it).
    struct Region {
        std::vector<int> rows, particles, boundary;
    };
    // The part of the "breaks decided" proof (SafeRange) of the rows that a region's CG leaves
    // alone (neither in the region nor on its boundary), summed once per region.
    struct Outside {
        double scaled = 0.0;   // Σ r_k² / d_k
        double squared = 0.0;  // Σ r_k²
        double room = INFINITY; // min of the distance to the break range × √d_k
        bool beyond = false;   // some row beyond its break range
    };
    // A solve's "breaks decided" stop.
    struct Decide {
        const SafeRange* safe = nullptr; // null: the stop is not tried
        double residual = 0.0;           // ‖b − Aλ‖ of a confirmed stop
    };
    // A region's rows copied out contiguously, its particles renumbered 0.. in region order:
    // CG multiplies by it 30-150 times, and reading rows through an index list into the whole
    // system's arrays (up to 100,000 rows) was most of a solve's time (cache misses).
    // One is kept per system and refilled for each region, so its buffers are allocated once.
    // Ends are kept as the address of their particle's sum (BlockRows), so the multiply forms no
    // address from a particle number (cg2: 2 instructions a row fewer in the scatter than int
    // offsets), and sums padded to 4 doubles, so one AVX2 register holds one.
    struct Block {
        // The first rowCount rows of `ends` and `normal` are the block's (the buffers only grow).
        size_t rowCount = 0;
        std::vector<double*> ends;              // sum of each row's first and second end (in `scratch`)
        std::vector<double> normal;             // 3 a row, then one +0 (BlockRows)
        std::vector<double> inverseMass;        // per block particle
        std::vector<int> number;                // block particle of each system particle in the region
        std::vector<double*> sumOf;             // its sum (the address `ends` holds)
        std::vector<int> edgeA, edgeB;          // block particle of each end of the boundary rows, -1 outside
        // M⁻¹ Jᵀ x per block particle after multiply (kBlockStride each), from sums(): the buffer
        // has room to start them on a 64-byte line, so no particle's 32 bytes straddle two lines.
        // (Sized by copy(), which points `ends` into it; nothing else resizes it.)
        mutable std::vector<double> scratch;
        double* sumsStart = nullptr; // sums(): the first 64-byte line in `scratch`
        double* sums() const { return sumsStart; }
        void copy(const ConstraintSystem& system, const Region& region);
        // The rows for the products (multiplyBlock, multiplyDirection), with `scratch` as their
        // sums; they hold until the next copy().
        BlockRows rows() const;
        // y = A_RR x in multiplyRows' operations and order, so the same bits.
        void multiply(const Eigen::VectorXd& x, Eigen::VectorXd& y) const;
        // M⁻¹ Jᵀ x of block particle i after multiply.
        Eigen::Vector3d acceleration(int i) const {
            return Eigen::Map<const Eigen::Vector3d>(sums() + kBlockStride * i);
        }
        // 1/d_j of block row j: 1 / (1/m_a + 1/m_b), as CG's Jacobi preconditioner forms it.
        double inverseDiagonal(size_t row) const {
            return 1.0 / (inverseMass[particleOf(ends[2 * row])] + inverseMass[particleOf(ends[2 * row + 1])]);
        }
        // The block particle whose sum is at `sum`.
        size_t particleOf(const double* sum) const { return size_t(sum - sums()) / kBlockStride;
        }
    };
    // Particles a warm solve's regions have taken so far (kept across its rounds): a flag per
    // local particle and the list of them. Kept by the system and cleared by the list, so a
    // solve near a few impacts writes no buffer as long as the body.
    struct Taken {
        std::vector<char> flag;
        std::vector<int> list;
        size_t sorted = 0; // the first entries of `list`, ascending (regionAround sorts the rest in)
        void clear(size_t particleCount);
    };
    // A row and a particle mark per local row and particle for regionAround and outsideOf, all
    // zero between their calls (each clears the entries it set).
    struct Marks {
        std::vector<char> rows, particles;
        // Sized for the system; all zeros, since every user clears what it set.
        void fit(size_t rowCount, size_t particleCount);
    };
    Region everyRow() const;
    void indexRowsByParticle();
    // Row data of lattice link `link` between local particles a and b, appended.
    void appendRow(const Lattice& lattice, int link, int a, int b);
    // Row `row`'s data set to that link's (the row exists).
    void setRow(size_t row, const Lattice& lattice, int link, int a, int b);
    // Row `from`'s data and λ copied to row `to` (addJoinedRows' merge).
    void moveRow(size_t from, size_t to, Eigen::VectorXd& lambda);
    // The seven row arrays and λ resized to `count` rows, the first rows kept (the caller sets
    // any new ones): restrictTo's shrink and addJoinedRows' growth.
    void resizeRows(size_t count, Eigen::VectorXd& lambda);
    // restrictTo's part for the links joined since the system was built or restricted: their
    // rows merged in, in link order, with λ = 0.
    void addJoinedRows(const Lattice& lattice, Eigen::VectorXd& lambda);
    // Every row of the free particles within `hops` links of a free end of a row whose
    // residual is above `floor` and whose scaled residual |r_k|/√d_k is above `scaledFloor` (`taken`
    // holds the particles taken, kept across rounds).
    Region regionAround(const Eigen::VectorXd& residual, double floor, double scaledFloor, int hops,
                        Taken& taken) const;
    Outside outsideOf(const Region& region, const Eigen::VectorXd& residual, const Eigen::VectorXd& lambda,
                      const SafeRange& safe) const;
    // What a solve or a region's CG stopped for.
    enum class Stop { Tolerance, Safe, BreaksDecided };
    // Jacobi-preconditioned CG on A_RR δ = r_R, added to λ on the region's rows, until
    // ‖r_R - A_RR δ‖ <= goal or the iterations run out, or (Stop::Safe) until the residual's
    // Jacobi-scaled norm is at most `safeGoal`, or (Stop::BreaksDecided, with `decide.safe`) until
    // the breaks are proven decided on the whole residual (the region's part formed again, the
    // rest's by outsideOf); the proof is complete when it returns so.
    Stop solveRegion(const Region& region, const Eigen::VectorXd& residual, double goal, double safeGoal,
                     Decide& decide, double bNorm, Eigen::VectorXd& lambda,
                     const ConstraintSolverSettings& settings, SolveResult& result) const;
    // What the residual r of λ proves about the exact solution (SafeRange): inside the safe
    // range (Stop::Safe), the breaks decided (Stop::BreaksDecided, when `safe` has a break
    // range), or nothing (Stop::Tolerance). `goal`, when given, receives the scaled residual
    // norm that would prove it safe with λ unchanged.
    Stop proven(const Eigen::VectorXd& residual, const Eigen::VectorXd& lambda, const SafeRange& safe,
                double* goal) const;
    // Whether a row is decided: its λ's distance to the break range's nearer end, × √d_k,
    // above `reach` (false for NaN), so the exact λ is on the same side (SafeRange). For
    // `proven` and a region's confirmation (CG's own check, which divides by its √(1/d_k),
    // rounds differently and stays its own).
    bool decidedRow(const SafeRange& safe, size_t row, double lambda, double reach) const;

    // keptRightHandSide's b and what it is of (`forces` empty: nothing kept).
    struct Rhs {
        Eigen::VectorXd forces, b;
        Eigen::Vector3d omega;
    };
    // Row k of b = -J̇ q̇ - J M⁻¹ Q (rightHandSide).
    double rightHandSideRow(size_t k, const Eigen::VectorXd& forces, const Eigen::Vector3d& omega) const;

    // A λ kept with the λ it is of, from one solve to the next: a warm solve starts from the λ
    // the last one ended with, so its first residual needs no product over every row, and after
    // a region's CG only the rows at the region's particles are formed again. 3 of a rest step's
    // 4 passes of the multiply over every row on the 55,411-tet Spot were these products.
    struct Product {
        Eigen::VectorXd lambda, rows;              // λ (empty: nothing kept) and A λ per row
        std::vector<Eigen::Vector3d> acceleration; // M⁻¹ Jᵀ λ per particle
    };
    // A x: the kept product when it is of x (the same bits), else the multiply over every row,
    // then kept. Valid until the product is next changed (productOf, updateProduct, restrictTo).
    const Eigen::VectorXd& productOf(const Eigen::VectorXd& x) const;
    // The kept product after x changed on the region's rows only: the accelerations of its
    // particles and the rows at them formed again in multiply()'s order of operations (each
    // particle's rows ascending, as the multiply adds them), so the values are the multiply's.
    void updateProduct(const Region& region, const Eigen::VectorXd& x) const;

    std::vector<int> particles_, links_;
    int joinedAtBuild_ = 0;                     // Lattice::joinedCount() when built (or restricted)
    bool ascending_ = true;                     // rows in strictly ascending link order
    std::vector<int> rowA_, rowB_;              // local particle of each end
    std::vector<Eigen::Vector3d> normal_;
    std::vector<double> length_;
    // d_k = A_kk = |n_k|² (1/m_a + 1/m_b) of each row, as assemble() forms it (and so the
    // bound's Â), and √d_k: the proofs (SafeRange) scale every row by them.
    std::vector<double> diagonal_, rootDiagonal_;
    std::vector<double> inverseMass_;           // per local particle, 0 when fixed
    std::vector<int> rowStart_, rowsOf_;        // the rows at each local particle (CSR)
    mutable std::vector<Eigen::Vector3d> scratch_;
    mutable std::vector<double> paddedSums_; // multiplyRows' AVX2 sums (kBlockStride a particle)
    mutable Block block_;                       // solveRegion's copy of its region
    mutable Product product_;
    mutable Rhs rhs_;
    mutable Taken taken_;
    mutable Marks marks_;
};

} // namespace shatter::lattice
