#!/usr/bin/env bash
# The main job: installs what is missing, builds (Release) and runs anisurf on
# the bundled demo (assets/demo.mesh + assets/demo.sol: a sphere whose metric
# asks for thin triangles along a wavy band).
# - With a display: opens the editor on the demo (Step / Run the adaptation).
# - Without one: runs the editor's demo script headless (OSMesa), which writes
#   out/demo_input.png, out/demo_adapted.png, out/demo_worst.png,
#   out/demo_g1.png and the adapted mesh out/demo_adapted.mesh + .sol.
# - A build without GL (-DANISURF_WITH_GL=OFF) adapts the demo with
#   `anisurf adapt` and writes out/demo_adapted.mesh + .sol.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh
bin="${ANISURF_BUILD_DIR:-build}/app/anisurf"
mkdir -p out
has_command() { "$bin" --help | grep -qE "^  $1 "; }
if has_command editor; then
  if [[ -n "${DISPLAY:-}" ]]; then
    exec "$bin" assets/demo.mesh assets/demo.sol
  fi
  "$bin" --script assets/demo.anisurf --headless
  "$bin" quality out/demo_adapted.mesh --sol out/demo_adapted.sol
  echo "demo: wrote out/demo_input.png, out/demo_adapted.png, out/demo_worst.png, out/demo_g1.png"
  echo "      and the adapted mesh out/demo_adapted.mesh (+ .sol)"
else
  "$bin" adapt assets/demo.mesh -sol assets/demo.sol -o out/demo_adapted.mesh
  echo "demo: wrote out/demo_adapted.mesh (+ .sol); this build has no renderer (-DANISURF_WITH_GL=ON adds it)"
fi
