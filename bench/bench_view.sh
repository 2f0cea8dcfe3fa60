#!/usr/bin/env bash
# Orbit frame rates of `anisurf view` on llvmpipe under Xvfb at 1280x800
# (issue #15): the falcon (75k triangles) and a 1.8M-triangle sphere
# (sphere20k adapted to size 0.004, made once into $WORK, several minutes).
# Each case runs RUNS times, the load average printed beside each figure; the
# orbit line says what was drawn (resolution, samples, triangles, proxy). With
# --compare OTHER_ANISURF, that binary runs the same cases back to back.
# Acceptance: falcon >= 40 fps, the sphere >= 10 fps (a quiet machine).
# Usage: bench/bench_view.sh [--runs N] [--frames N] [--full-detail] [--compare BINARY]
set -euo pipefail
cd "$(dirname "$0")/.."
runs=3
frames=60
extra=()
binaries=("${ANISURF_BUILD_DIR:-build}/app/anisurf")
while (($#)); do
  case "$1" in
    --runs) runs="$2"; shift 2 ;;
    --frames) frames="$2"; shift 2 ;;
    --full-detail) extra+=(--bench-full-detail); shift ;;
    --compare) binaries+=("$2"); shift 2 ;;
    *) echo "usage: bench/bench_view.sh [--runs N] [--frames N] [--full-detail] [--compare BINARY]" >&2; exit 2 ;;
  esac
done
shared="${ANISURF_SHARED:-$PWD/../shared}"  # the shared data beside the checkout (the cwd is the checkout)
work="${WORK:-${TMPDIR:-/tmp}/anisurf-bench-view}"
mkdir -p "$work"
sphere="$work/sphere18m.mesh"
if [[ ! -s "$sphere" ]]; then
  echo "making $sphere (sphere20k adapted to size 0.004) ..." >&2
  "${binaries[0]}" adapt "$shared/bench/inputs/sphere20k.mesh" --size 0.004 -o "$sphere" >"$work/adapt.log"
fi

orbit() {  # binary mesh
  xvfb-run -a -s "-screen 0 1280x800x24" "$1" view "$2" --bench-orbit "$frames" "${extra[@]}" 2>&1 | grep '^orbit:'
}

for mesh in "$shared/meshes/falcon.mesh" "$sphere"; do
  echo "## $(basename "$mesh")"
  for ((i = 1; i <= runs; ++i)); do
    for bin in "${binaries[@]}"; do
      load=$(cut -d' ' -f1 /proc/loadavg)
      echo "load $load  $bin: $(orbit "$bin" "$mesh")"
    done
  done
done
