#include <shatter/plugin/lattice/FractureAnalysis.h>
#include <shatter/plugin/common/Stopwatch.h>
#include <shatter/plugin/lattice/CleavingPlane.h>
#include <shatter/plugin/lattice/RowUtilisation.h>


namespace shatter::lattice {

namespace {

class Step {
public:
    Step(Lattice& lattice, LatticePiece& piece, const Eigen::VectorXd& loads, const Eigen::Vector3d& omega,
         const FractureAnalysisSettings& s, Random& random)
        : lattice_(lattice), piece_(piece), loads_(loads), omega_(omega), s_(s), random_(random) {}

    FractureReport run() {
        const auto t0 = SteadyClock::now();
        piece_.constraintSystem(lattice_);
        report_.assemblySeconds += secondsSince(t0);
        bool weakened = !s_.breaking.weakenByLoad;
        while (true) {
            solveUntilNothingBreaks();
            if (weakened) break;
            weakened = true;
            if (!weakenByLoad()) break; // no link worn out: the forces stand
        }
        return report_;
    }

private:
    // `mayStopAtBreaks`: whether the solve may stop once it has proven which links break (not
    // in the last round, whose λ the weakening reads).
    void solve(bool mayStopAtBreaks) {
        auto t = SteadyClock::now();
        const ConstraintSystem& system = *piece_.system;
        const Eigen::VectorXd& b = system.keptRightHandSide(loads_, omega_);
        gatherStrengths();
        report_.assemblySeconds += secondsSince(t);
        t = SteadyClock::now();
        const SafeRange& safe = safeRange(mayStopAtBreaks);
        const SolveResult r = system.solve(b, piece_.lambda, s_.solver, piece_.eigenvalueBound > 0.0 ? &safe : nullptr);
        report_.solveSeconds += secondsSince(t);
        ++report_.solves;
        report_.iterations += r.iterations;
        report_.worstResidual = std::max(report_.worstResidual, r.residual);
        report_.converged = report_.converged && r.converged;
        report_.provenSafe += r.provenSafe ? 1 : 0;
        report_.breaksDecided += r.breaksDecided ? 1 : 0;
    }

    // The current strength of each row's link, in row order: one pass over the (150-byte)
    // Links per solve, read by the safe range and by the break and weakening checks after it.
    void gatherStrengths() {
        const ConstraintSystem& system = *piece_.system;
        strength_.resize(size_t(system.rowCount()));
        for (int r = 0; r < system.rowCount(); ++r) strength_[size_t(r)] = lattice_.links()[system.links()[r]].strength;
        strengthsCurrent_ = true;
    }

    // The forces at which no link breaks (utilisation > 1) or, when loads weaken links, none
    // weakens (utilisation >= the onset): a solve that proves the exact forces inside this
    // range may stop before its tolerance, since its λ then changes nothing but the next warm
    // start. Its break range (utilisation > 1 outside) lets a solve stop once it has proven
    // which links break: those break and the system is solved again without them, so only the
    // last solve of a step, where nothing breaks, needs λ itself (and the last round allowed,
    // which has no break range: when the rounds run out, the weakening reads its λ). The proofs are
    // ConstraintSystem::solve's (SafeRange); the full solve's own answer is exact only to its
    // tolerance, so "the same breaks" holds to that tolerance.
    // Formed in the piece's kept buffers (LatticePiece::rows), so that a rest step allocates
    // and zeroes no array as long as the body; the last round's, without a break range, in
    // this step's own.
    const SafeRange& safeRange(bool withBreakRange) {
        if (!(piece_.eigenvalueBound > 0.0)) return withBreakRange ? piece_.rows.safe : lastRound_;
        const ConstraintSystem& system = *piece_.system;
        const double ratio = lattice_.material().compressionRatio;
        const double limit = s_.breaking.weakenByLoad ? s_.breaking.weakeningOnset : 1.0;
        const size_t rows = size_t(system.rowCount());
        SafeRange& safe = withBreakRange ? piece_.rows.safe : lastRound_;
        safe.eigenvalueBound = piece_.eigenvalueBound;
        if (!withBreakRange) { // rare (the rounds ran out): every row
            lastRound_.lower.resize(rows);
            lastRound_.upper.resize(rows);
            lastRound_.breakLower.clear();
            lastRound_.breakUpper.clear();
            for (size_t r = 0; r < rows; ++r) formRange(lastRound_, r, std::max(0.0, strength_[r]), limit, ratio);
            return lastRound_;
        }
        // The piece's kept range: each row formed again only where its (clamped) strength is not
        // the one it was formed from, which at rest is nowhere. A clamped strength is never NaN
        // or −0, so == is a bit compare here; NaN marks a row never formed.
        LatticePiece::RowBuffers& kept = piece_.rows;
        if (kept.formedFrom.size() != rows || kept.limit != limit || kept.ratio != ratio) {
            kept.formedFrom.assign(rows, NAN);
            kept.limit = limit;
            kept.ratio = ratio;
        }
        safe.lower.resize(rows);
        safe.upper.resize(rows);
        safe.breakLower.resize(rows);
        safe.breakUpper.resize(rows);
        for (size_t r = 0; r < rows; ++r) {
            const double strength = std::max(0.0, strength_[r]);
            if (strength == kept.formedFrom[r]) continue;
            kept.formedFrom[r] = strength;
            formRange(safe, r, strength, limit, ratio);
            safe.breakLower[r] = -strength;
            safe.breakUpper[r] = ratio * strength;
        }
        return safe;
    }

    // utilisation: tension -λ against the strength, compression λ against strength × ratio
    // (a link of no strength gets an empty range).
    static void formRange(SafeRange& safe, size_t row, double strength, double limit, double ratio) {
        safe.lower[row] = -limit * strength;
        safe.upper[row] = limit * ratio * strength;
    }

    void solveUntilNothingBreaks() {
        for (int round = 0; round < s_.breaking.maxRounds; ++round) {
            solve(round + 1 < s_.breaking.maxRounds);
            const auto t = SteadyClock::now();
            const std::vector<int> overloaded = overloadedLinks(round == 0 && report_.solves == 1);
            if (overloaded.empty()) {
                report_.breakingSeconds += secondsSince(t);
                return;
            }
            const size_t before = report_.broken.size();
            strengthsCurrent_ = false;
            for (int k : overloaded) {
                lattice_.breakLink(k);
                report_.broken.push_back(k);
            }
            for (int k : overloaded)
                spreadDamage(lattice_, k, s_.spreading, s_.breaking.removalFraction, random_, report_.broken);
            runCracks(lattice_, report_.broken, before);
            report_.breakingSeconds += secondsSince(t);
            const auto a = SteadyClock::now();
            piece_.rebuild(lattice_);
            report_.assemblySeconds += secondsSince(a);
        }
    }

    // Also lists the rows at or above the weakening onset (`loadedRows_`), which weakenByLoad
    // reads when nothing changed since: the same utilisations, so it needs no pass of its own.
    std::vector<int> overloadedLinks(bool first) {
        const ConstraintSystem& system = *piece_.system;
        const double ratio = lattice_.material().compressionRatio;
        const double onset = s_.breaking.weakenByLoad ? s_.breaking.weakeningOnset : 1.0;
        std::vector<int> out;
        loadedRows_.clear();
        // Arrays, row count and the running maximum in locals: with the appends in the loop the
        // compiler loaded them again on every row (33 instructions a row). The same operations.
        const double* const strengths = strength_.data();
        const double* const lambdas = piece_.lambda.data();
        const int* const links = system.links().data();
        auto pick = [&](size_t r, double u) {
            if (!(u < onset)) loadedRows_.push_back(int(r)); // weakenByLoad's test: a NaN is listed too
            if (u > 1.0) out.push_back(links[r]);
        };
        const double most = scanUtilisation(size_t(system.rowCount()), strengths, lambdas, ratio, onset,
                                            report_.maxUtilisation, pick);
        if (first) report_.maxUtilisation = most;
        loadedRowsCurrent_ = out.empty(); // breaks change the rows and λ
        return out;
    }

    // Survivors loaded beyond the onset lose their load from their strength; returns whether
    // any link fell below the removal threshold (then the forces must be solved again).
    bool weakenByLoad() {
        const auto t = SteadyClock::now();
        const ConstraintSystem& system = *piece_.system;
        const double ratio = lattice_.material().compressionRatio;
        const size_t before = report_.broken.size();
        // The rows the last overloadedLinks found at or above the onset, when it read these
        // strengths and λ (the last round found nothing to break); else every row.
        const bool listed = loadedRowsCurrent_ && strengthsCurrent_;
        if (!strengthsCurrent_) gatherStrengths(); // the rounds ran out after breaks
        strengthsCurrent_ = false;
        loadedRowsCurrent_ = false;
        const int count = listed ? int(loadedRows_.size()) : system.rowCount();
        for (int i = 0; i < count; ++i) {
            const int r = listed ? loadedRows_[size_t(i)] : i;
            if (utilisation(strength_[size_t(r)], piece_.lambda[r], ratio) < s_.breaking.weakeningOnset) continue;
            const int k = system.links()[r];
            const Link& l = lattice_.links()[k];
            lattice_.weaken(k, tensileEquivalent(piece_.lambda[r], ratio));
            if (l.strength < s_.breaking.removalFraction * l.baseStrength) {
                lattice_.breakLink(k);
                report_.broken.push_back(k);
            }
        }
        runCracks(lattice_, report_.broken, before);
        const bool removed = report_.broken.size() > before;
        report_.breakingSeconds += secondsSince(t);
        if (removed) piece_.rebuild(lattice_);
        return removed;
    }

    Lattice& lattice_;
    LatticePiece& piece_;
    const Eigen::VectorXd& loads_;
    Eigen::Vector3d omega_;
    const FractureAnalysisSettings& s_;
    Random& random_;
    FractureReport report_;
    std::vector<double>& strength_ = piece_.rows.strength; // per row of the piece's system (gatherStrengths)
    SafeRange lastRound_; // the last round's safe range, without a break range
    bool strengthsCurrent_ = false; // no link of the system broke or weakened since the gathering
    std::vector<int> loadedRows_;   // rows at or above the weakening onset (overloadedLinks), ascending
    bool loadedRowsCurrent_ = false; // loadedRows_ is of the current rows, λ and strengths
};

} // namespace

void FractureAnalysisSettings::check(const std::string& body) const {
    solver.check(body);
    breaking.check(body);
    spreading.check(body);
}

FractureReport analyseFracture(Lattice& lattice, LatticePiece& piece, const Eigen::VectorXd& loads,
                               const Eigen::Vector3d& omega, const FractureAnalysisSettings& settings, Random& random) {
    return Step(lattice, piece, loads, omega, settings, random).run();
}

} // namespace shatter::lattice
