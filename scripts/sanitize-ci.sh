#!/usr/bin/env bash
# The sanitized part of CI (scripts/test.sh runs it after the Release suite): one clang build
# in ./build-fuzz with AddressSanitizer + UndefinedBehaviorSanitizer and libFuzzer's coverage
# instrumentation (-DSHATTER_FUZZ=ON), which
#   - compiles the libraries with clang (Debian's clang 14), so a clang break fails CI;
#   - runs the fast suites under the sanitizers: SUITES below (geometry, lattice, the fuzz
#     regression replay, bullet_ext, fracture). Left out, and run only in the Release suite: the MPM
#     solver's and the demos' tests (the MPM validations take minutes even in Release and time
#     out under ASan), oriented/integration (long rest tests) and RELEASE_ONLY below.
#     scripts/sanitize.sh runs everything sanitized, without a time budget.
#   - runs each fuzz target for FUZZ_SECONDS (default 20) from the seeds and the regression corpus,
#     two at a time, each on its own core.
# Measured cold (no ccache) on the 2-core CI machine: see the "Tests and tooling" README section.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${SHATTER_FUZZ_BUILD:-$root/build-fuzz} # another folder, e.g. to time a cold build
SUITES=(shatter_tests_geometry shatter_tests_lattice shatter_tests_fuzz shatter_tests_bullet shatter_tests_bullet_lattice
        shatter_tests_bullet_mpm shatter_tests_fracture shatter_tests_bullet_fracture)
command -v clang++ >/dev/null || { echo "sanitize-ci.sh: clang++ is needed (scripts/debian-packages.txt)" >&2; exit 1; }
CC=clang CXX=clang++ cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSHATTER_FUZZ=ON \
  -DSHATTER_BUILD_DEMOS=OFF >/dev/null
cmake --build "$build" -j "$(nproc)" --target "${SUITES[@]}" shatter-fuzz-obj shatter-fuzz-tetgen shatter-fuzz-scene \
  shatter-fuzz-pattern
labels=$(IFS='|'; echo "^(${SUITES[*]})\$")
# Run in Release only (the Release suite runs every test): the long physics runs below, each
# more than 40 s under the sanitizers on this machine and together half of the sanitized suite's
# time (2026-11-29: 1,186 of 2,315 test-seconds), while a shorter sanitized test walks the same
# code: Spot's drops and the fine statue (RealShape.SpotAnchoredByItsHooves...), the CG solve to
# the direct solution (14 other ConstraintSolver tests), two of the fragment budget's three runs
# (PartsLeftForLater...), the jelly's 10,000-step rest and its every-fourth-substep rest (16
# other SoftCoupling tests), the smallest-eigenvalue check (every lattice solve computes the
# bound), debris on the ground (5 other LatticeDebris tests), and the merged fragments' touching
# parts (2 other MergedFragment tests).
RELEASE_ONLY=(
  'RealShape\.SpotDroppedAndHitBreaksWithinTheSpeedBound'
  'RealShape\.SliverRichSpotDroppedAndHitBreaksWithinTheSpeedBound'
  'RealShape\.FineSpotStatueShedsNoPieceBelowTheMinimumFragmentSize'
  'ConstraintSolver\.ResidualBelowToleranceAndLambdaConvergesToTheDirectSolution'
  'LatticeFragmentBudget\.SameSeedGivesTheSameBits'
  'LatticeFragmentBudget\.NoStepMakesMoreBodiesThanTheBudgetAndEveryPartComesApart'
  'SoftCoupling\.RestingJellyNeitherDriftsNorGainsEnergyOver10000Steps'
  'SoftCoupling\.AJellyAwayFromMovingBodiesStepsOncePerItsSubstepsAndStillRests'
  'EigenvalueBound\.BelowTheSmallestEigenvalueAndWithinAFactorOfTwoOfIt'
  'LatticeDebris\.DebrisTouchTheGroundButNeverEachOther'
  'MergedFragment\.EveryFragmentIsJoinedWhereverItsPartsTouch'
)
release_only=$(IFS='|'; echo "^(${RELEASE_ONLY[*]})\$")
# A renamed test would silently fall back into the sanitized run (40-400 s each): say so instead.
for name in "${RELEASE_ONLY[@]}"; do
  ctest --test-dir "$build" -N -R "^${name}\$" | grep -q '^Total Tests: 1$' ||
    { echo "sanitize-ci.sh: RELEASE_ONLY names no test: $name" >&2; exit 1; }
done
ASAN_OPTIONS=detect_leaks=1 LSAN_OPTIONS=suppressions=$root/tests/sanitizers/lsan.supp \
  UBSAN_OPTIONS=print_stacktrace=1 ctest --test-dir "$build" -j2 --output-on-failure -L "$labels" -E "$release_only"
# Two fuzz targets at a time (CI has two cores): each still runs FUZZ_SECONDS on its own core.
FUZZ_JOBS=${FUZZ_JOBS:-2} "$root/scripts/fuzz.sh" "${FUZZ_SECONDS:-20}"
