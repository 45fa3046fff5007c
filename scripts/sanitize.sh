#!/usr/bin/env bash
# The test suite under AddressSanitizer + UndefinedBehaviorSanitizer (Debug, ./build-asan).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/install-deps.sh"
cmake -S "$root" -B "$root/build-asan" -DCMAKE_BUILD_TYPE=Debug -DSHATTER_SANITIZE=ON >/dev/null
cmake --build "$root/build-asan" -j "$(nproc)"
cd "$root/build-asan"
ASAN_OPTIONS=detect_leaks=1 LSAN_OPTIONS=suppressions=$root/tests/sanitizers/lsan.supp UBSAN_OPTIONS=print_stacktrace=1 ctest -j2 --output-on-failure "$@"
