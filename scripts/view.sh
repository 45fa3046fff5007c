#!/usr/bin/env bash
# Plays a demo run in the browser: scripts/view.sh out/wall [PORT]
# Installs the viewer's npm packages if needed (pinned by demos/viewer/package-lock.json), serves
# the viewer with the run directory on 127.0.0.1 only, and prints the address to open.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
if [[ $# -lt 1 || ! -d "$1" ]]; then
  echo "usage: scripts/view.sh RUN_DIR [PORT]   (RUN_DIR: a demo's --out directory, e.g. out/drop)" >&2
  exit 2
fi
run=$(cd "$1" && pwd)
port=${2:-8765}
for f in scene.glb summary.json; do
  if [[ ! -f "$run/$f" ]]; then
    echo "scripts/view.sh: error: $run/$f is missing (run a demo without --no-gltf first)" >&2
    exit 1
  fi
done
viewer=$root/demos/viewer
if [[ ! -f "$viewer/node_modules/three/package.json" || "$viewer/package-lock.json" -nt "$viewer/node_modules" ]]; then
  command -v npm >/dev/null || { echo "scripts/view.sh: error: npm is needed (Debian: apt-get install npm)" >&2; exit 1; }
  npm ci --prefix "$viewer" --no-audit --no-fund --loglevel=error
fi
site=$(mktemp -d)
trap 'rm -rf "$site"' EXIT
for f in index.html main.js viewer.css node_modules; do ln -s "$viewer/$f" "$site/$f"; done
ln -s "$run" "$site/run"
echo "Shatter viewer for $run: http://127.0.0.1:$port/   (Ctrl-C stops it)"
python3 -m http.server --bind 127.0.0.1 --directory "$site" "$port" >/dev/null 2>&1
