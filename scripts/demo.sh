#!/usr/bin/env bash
# README command 1: install what is missing, build, and run the flagship demo (shatter-drop).
# Extra arguments go to the demo, e.g. scripts/demo.sh --mesh my.obj
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/build.sh"
"$root/build/bin/shatter-drop" --out "$root/out/drop" "$@"
