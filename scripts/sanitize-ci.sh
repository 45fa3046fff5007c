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
# Run in Release only: the drop of TetGen's 10k-tet Spot (65 s of ASan CPU). Under the
# sanitizers the shipped Spot's drop (RealShape.SpotDroppedAndHit...) takes the same path.
RELEASE_ONLY='^RealShape\.SliverRichSpotDroppedAndHitBreaksWithinTheSpeedBound$'
ASAN_OPTIONS=detect_leaks=1 LSAN_OPTIONS=suppressions=$root/tests/sanitizers/lsan.supp \
  UBSAN_OPTIONS=print_stacktrace=1 ctest --test-dir "$build" -j2 --output-on-failure -L "$labels" -E "$RELEASE_ONLY"
# Two fuzz targets at a time (CI has two cores): each still runs FUZZ_SECONDS on its own core.
FUZZ_JOBS=${FUZZ_JOBS:-2} "$root/scripts/fuzz.sh" "${FUZZ_SECONDS:-20}"
