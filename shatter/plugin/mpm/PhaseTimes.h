#pragma once
// Wall time spent in each stage of the substeps so far (Solver2D::phaseTimes): where a
// program's time goes, per stage, with whatever waiting its threads did inside the stage.
// Read by shatter-bench-mpm --phases; a clock read per stage costs ~20 ns against a
// substep of ~1 ms.
#include <array>
#include <chrono>
#include <string_view>

namespace shatter::mpm {

struct PhaseTimes {
    enum Phase {
        Setup,        // loads, crack segments, grid resize and clear, stripe sort
        Fields,       // crack field assignment (line-crossing tests)
        Scatter,      // particles to grid
        GridUpdate,   // grid velocities, crack contact, collisions
        Gather,       // grid to particles, stresses for the next substep
        CrackAdvect,  // crack points follow the material
        TipAnalysis,  // J-integral, K, growth
        Count
    };
    static constexpr std::array<std::string_view, Count> names{
        "setup (clear, sort)", "field assignment", "particles to grid", "grid update",
        "grid to particles",   "crack advection",  "J-integral, growth"};

    std::array<double, Count> seconds{};

    // Times consecutive stages: mark(k) adds the time since the last mark to stage k.
    class Clock {
    public:
        explicit Clock(PhaseTimes& t) : times_(t), last_(std::chrono::steady_clock::now()) {}
        void mark(Phase k) {
            const auto now = std::chrono::steady_clock::now();
            times_.seconds[size_t(k)] += std::chrono::duration<double>(now - last_).count();
            last_ = now;
        }

    private:
        PhaseTimes& times_;
        std::chrono::steady_clock::time_point last_;
    };
};

} // namespace shatter::mpm
