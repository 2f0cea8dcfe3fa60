#!/usr/bin/env bash
# Builds the libFuzzer targets (clang, ASan + UBSan) into build-fuzz/ and runs
# each for SECONDS (default 60), one after the other; prints one line per
# reader: executions, new corpus entries, crashes (saved under
# build-fuzz/artifacts/READER/: copy each into tests/fuzz/corpus/READER/ once
# fixed, the replay test then keeps it fixed).
# Usage: scripts/fuzz.sh [--seconds N] [READER ...]  (readers: medit meshb sol
# solb obj off ply stl gltf glb msh vtu vtp vtk; default all)
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=60
readers=()
while [[ $# -gt 0 ]]; do
  case "$1" in
    --seconds) seconds="$2"; shift 2 ;;
    -*) echo "usage: scripts/fuzz.sh [--seconds N] [READER ...]" >&2; exit 2 ;;
    *) readers+=("$1"); shift ;;
  esac
done
[[ ${#readers[@]} -gt 0 ]] || readers=(medit meshb sol solb obj off ply stl gltf glb msh vtu vtp vtk)
declare -A extension=([medit]=mesh [meshb]=meshb [sol]=sol [solb]=solb [obj]=obj [off]=off [ply]=ply [stl]=stl
                      [gltf]=gltf [glb]=glb [msh]=msh [vtu]=vtu [vtp]=vtp [vtk]=vtk)
for r in "${readers[@]}"; do
  [[ -n "${extension[$r]:-}" ]] || { echo "fuzz: unknown reader '$r'" >&2; exit 2; }
done
command -v clang++ >/dev/null || { echo "fuzz: clang++ not found (apt-get install clang)" >&2; exit 1; }

build=build-fuzz
generator=()
command -v ninja >/dev/null && generator=(-G Ninja)
[[ -f $build/CMakeCache.txt ]] || cmake -S . -B $build "${generator[@]}" -DCMAKE_CXX_COMPILER=clang++ \
  -DCMAKE_BUILD_TYPE=RelWithDebInfo -DANISURF_FUZZ=ON -DANISURF_WITH_GL=OFF -DANISURF_BUILD_TESTS=OFF \
  -DANISURF_BUILD_BENCH=OFF
targets=()
for r in "${readers[@]}"; do targets+=(fuzz_"$r"); done
cmake --build $build -j "$(nproc)" --target "${targets[@]}"

status=0
for r in "${readers[@]}"; do
  # The working corpus grows across runs; the seeds are the test data of the
  # reader's extension and the committed corpus (seeds and reproducers).
  corpus=$build/corpus/$r
  artifacts=$build/artifacts/$r
  mkdir -p "$corpus" "$artifacts"
  shopt -s nullglob nocaseglob
  for f in tests/data/*."${extension[$r]}" tests/data/bad/*."${extension[$r]}" assets/*."${extension[$r]}" \
           tests/fuzz/corpus/"$r"/*; do
    cp -n "$f" "$corpus/" 2>/dev/null || true
  done
  shopt -u nullglob nocaseglob
  log=$build/fuzz_$r.log
  before=$(ls "$artifacts" | wc -l)
  "$build/tests/fuzz/fuzz_$r" "$corpus" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 \
    -max_len=65536 -print_final_stats=1 -artifact_prefix="$artifacts/" >"$log" 2>&1 || status=1
  runs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' || echo "?")
  added=$(grep -o 'stat::new_units_added: *[0-9]*' "$log" | grep -o '[0-9]*$' || echo "?")
  crashes=$(( $(ls "$artifacts" | wc -l) - before ))
  printf 'fuzz %-6s %4ss  %10s executions  %5s new inputs  %d crashes%s\n' "$r" "$seconds" "$runs" "$added" \
    "$crashes" "$( ((crashes)) && echo " (see $log, $artifacts)")"
  ((crashes == 0)) || status=1
done
exit $status
