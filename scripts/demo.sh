#!/usr/bin/env bash
# The main job: installs what is missing, builds (Release) and runs anisurf on
# the bundled demo (assets/demo.mesh + assets/demo.sol).
# With a display and the GL build: opens the viewer on the demo.
# Without a display: prints the demo's `anisurf info` and renders it headless
# to out/demo.png (OSMesa), writing every output under out/.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh
bin="${ANISURF_BUILD_DIR:-build}/app/anisurf"
mkdir -p out
"$bin" info assets/demo.mesh --sol assets/demo.sol
has_command() { "$bin" --help | grep -qE "^  $1 "; }
if [[ -n "${DISPLAY:-}" ]] && has_command view; then
  exec "$bin" view assets/demo.mesh assets/demo.sol
fi
"$bin" convert assets/demo.mesh out/demo.vtk --sol assets/demo.sol
if has_command shot; then
  "$bin" shot assets/demo.mesh --sol assets/demo.sol --glyphs --wire --view iso -o out/demo.png
  echo "demo: wrote out/demo.png and out/demo.vtk"
else
  echo "demo: wrote out/demo.vtk (this build has no renderer: configure with -DANISURF_WITH_GL=ON)"
fi
