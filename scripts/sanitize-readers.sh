#!/usr/bin/env bash
# The readers under AddressSanitizer + UBSan, the part of `scripts/test.sh
# --sanitize` that CI can afford: builds only the engine and anisurf_replay
# (tests/fuzz/replay_main.cpp) into build-san-readers/ with the sanitizers,
# then reads every test file, bad file, asset and fuzzing corpus entry (the
# seeds and every crash reproducer found so far) through the fuzzing entry
# functions. Any sanitizer report, invalid mesh or unexpected exception fails.
# Usage: scripts/sanitize-readers.sh   (CXX=clang++ builds faster, if installed)
set -euo pipefail
cd "$(dirname "$0")/.."
build=build-san-readers
flags="-O1 -g -fno-omit-frame-pointer -fsanitize=address,undefined,float-cast-overflow -fno-sanitize-recover=all"
generator=()
command -v ninja >/dev/null && generator=(-G Ninja)
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
[[ -f $build/CMakeCache.txt ]] || cmake -S . -B $build "${generator[@]}" "${launcher[@]}" -DCMAKE_BUILD_TYPE=None \
  -DANISURF_WITH_GL=OFF -DANISURF_BUILD_TESTS=OFF -DANISURF_BUILD_BENCH=OFF -DANISURF_READER_REPLAY=ON \
  -DCMAKE_CXX_FLAGS="$flags" -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" >/dev/null
cmake --build $build -j "$(nproc)" --target anisurf_replay
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:strict_string_checks=1:detect_stack_use_after_return=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
"$build/tests/fuzz/anisurf_replay" tests/data assets tests/fuzz/corpus
