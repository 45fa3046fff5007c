#!/usr/bin/env bash
# Installs the npm packages the tests and the viewer use, at the versions their lock files pin
# (npm ci): the Khronos glTF validator (tests/demos/gltf), three.js and puppeteer-core (demos/viewer). Without npm it tries Debian's npm package; if npm
# still cannot run, it says so and the tests that need these packages are skipped.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
if ! command -v npm >/dev/null; then
  sudo=""
  if [[ $(id -u) -ne 0 ]] && command -v sudo >/dev/null; then sudo="sudo"; fi
  { $sudo apt-get install -y -qq --no-install-recommends npm >/dev/null; } 2>/dev/null || true
fi
if ! command -v npm >/dev/null; then
  echo "npm is not available: the glTF validator and browser viewer tests will be skipped" >&2
  exit 0
fi
for dir in tests/demos/gltf demos/viewer; do
  if [[ ! -d "$root/$dir/node_modules" || "$root/$dir/package-lock.json" -nt "$root/$dir/node_modules" ]]; then
    npm ci --prefix "$root/$dir" --no-audit --no-fund --loglevel=error
  fi
done
