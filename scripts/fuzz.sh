#!/usr/bin/env bash
# Builds the loaders' libFuzzer targets with clang (ASan + UBSan, the libraries instrumented
# too: -DSHATTER_FUZZ=ON) in ./build-fuzz and runs each for SECONDS, one after the other on one
# core (FUZZ_JOBS=N: N at a time, each on its own core; CI runs 2):
# scripts/fuzz.sh [SECONDS] [obj|tetgen|scene|pattern ...]   (default 60 s, every target).
# Inputs a target finds new go to build-fuzz/corpus/<target>; a crash, leak, timeout or
# out-of-memory stops that target, leaves the input in build-fuzz/findings/<target>/ and makes
# the script fail. Copy findings (fixed) into tests/fuzz/regressions/<target>/ with a name that
# says what they were; the test suite replays that folder in every build.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
seconds=${1:-60}
shift || true
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(obj tetgen scene pattern)
command -v clang++ >/dev/null || { echo "fuzz.sh: clang++ is needed (apt-get install clang)" >&2; exit 1; }
build=${SHATTER_FUZZ_BUILD:-$root/build-fuzz} # another folder, e.g. to time a cold build
CC=clang CXX=clang++ cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSHATTER_FUZZ=ON \
  -DSHATTER_BUILD_DEMOS=OFF >/dev/null
cmake --build "$build" -j "$(nproc)" --target "${targets[@]/#/shatter-fuzz-}"

# Seeds: the demos' own files and every past finding.
seeds() {
  case $1 in
    obj) echo "$root/demos/assets $root/tests/fuzz/regressions/obj" ;;
    tetgen) echo "$root/tests/fuzz/seeds/tetgen $root/tests/fuzz/regressions/tetgen" ;;
    scene) echo "$root/demos/scenes $root/tests/fuzz/regressions/scene" ;;
    pattern) echo "$root/tests/fuzz/seeds/pattern $root/tests/fuzz/regressions/pattern" ;;
  esac
}

# One target: its report is printed in one write when it ends (targets may run side by side);
# a finding also leaves $build/findings/<target>.failed.
fuzz_one() {
  local t=$1 report stats
  mkdir -p "$build/corpus/$t" "$build/findings/$t"
  report="== $t: $seconds s"
  # -rss_limit_mb / -malloc_limit_mb: one input may not take 2 GB; -timeout: nor 10 s.
  # shellcheck disable=SC2046
  if ! ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
      "$build/bin/shatter-fuzz-$t" "$build/corpus/$t" $(seeds "$t") -max_total_time="$seconds" \
      -rss_limit_mb=2048 -malloc_limit_mb=2048 -timeout=10 -print_final_stats=1 \
      -artifact_prefix="$build/findings/$t/" 2>"$build/findings/$t.log"; then
    touch "$build/findings/$t.failed"
    printf '%s\n%s\n' "$report" "$t: FINDING, see $build/findings/$t/ and $build/findings/$t.log"
    return
  fi
  stats=$(grep -E "stat::number_of_executed_units|stat::peak_rss_mb|cov:" "$build/findings/$t.log" | tail -3 || true)
  printf '%s\n%s\n' "$report" "$stats"
}

# FUZZ_JOBS targets at a time, each on its own core (default 1: one after the other). A job's
# status is read from its marker file, not from `wait`, which may have forgotten a job that
# ended before it was asked.
jobs_max=${FUZZ_JOBS:-1}
[[ $jobs_max =~ ^[1-9][0-9]*$ ]] || { echo "fuzz.sh: FUZZ_JOBS must be a positive integer, got '$jobs_max'" >&2; exit 2; }
for t in "${targets[@]}"; do rm -f "$build/findings/$t.failed"; done
for t in "${targets[@]}"; do
  while (($(jobs -rp | wc -l) >= jobs_max)); do wait -n || true; done
  fuzz_one "$t" &
done
wait
status=0
for t in "${targets[@]}"; do [[ -e $build/findings/$t.failed ]] && status=1; done
exit $status
