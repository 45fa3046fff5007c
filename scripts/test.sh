#!/usr/bin/env bash
# README command 2: install what is missing, build, and run the whole test suite; then the
# sanitized part (scripts/sanitize-ci.sh: a clang ASan+UBSan build of the fast suites, and each
# fuzz target for 20 s).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/build.sh"
"$root/scripts/install-npm-tools.sh"
cd "$root/build"
ctest -j2 --output-on-failure
"$root/scripts/sanitize-ci.sh"
